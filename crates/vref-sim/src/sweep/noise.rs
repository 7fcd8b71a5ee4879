//! Which knobs of [`SensorNoise`](crate::SensorNoise) a sweep scales.

use std::fmt;
use std::str::FromStr;

use crate::{SensorNoise, SimConfig, SweepError};

/// Factors on the configuration's own noise a sweep uses unless told
/// otherwise: none, half, as configured, double, fourfold.
pub const DEFAULT_LEVELS: [f64; 5] = [0.0, 0.5, 1.0, 2.0, 4.0];

/// A family of noise knobs, scaled together in both cameras.
///
/// Two knobs belong to neither family, because they are not errors of
/// one kind: `surface_bias` is a property of the position pipeline (a
/// share in [0, 1]; above 1 the position would lie beyond the seen
/// surface), and `segmentation` moves both the position and the feature
/// (a mask that bleeds into the background shifts its centroid and mixes
/// the background's colours in), so scaling it would confound the two.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NoiseSweep {
    /// Position errors along the line of sight: the per-object depth error
    /// (`depth`) and the per-frame depth scale error (`depth_scale`).
    Depth,
    /// Appearance errors that leave positions alone: histogram sampling
    /// noise (`pixel`), uncorrected white balance (`white_balance`) and
    /// exposure (`exposure`).
    Feature,
}

impl NoiseSweep {
    pub const ALL: [NoiseSweep; 2] = [NoiseSweep::Depth, NoiseSweep::Feature];

    pub fn name(self) -> &'static str {
        match self {
            NoiseSweep::Depth => "depth-noise",
            NoiseSweep::Feature => "feature-noise",
        }
    }

    /// `config` with this family's knobs of both cameras multiplied by
    /// `factor` and every other knob as it was.
    pub fn scaled(self, config: &SimConfig, factor: f64) -> SimConfig {
        let mut config = config.clone();
        for noise in [&mut config.robot.noise, &mut config.human.noise] {
            self.scale(noise, factor);
        }
        config
    }

    fn scale(self, noise: &mut SensorNoise, factor: f64) {
        match self {
            NoiseSweep::Depth => {
                noise.depth *= factor;
                noise.depth_scale *= factor;
            }
            NoiseSweep::Feature => {
                noise.pixel *= factor;
                noise.white_balance *= factor;
                noise.exposure *= factor;
            }
        }
    }
}

impl fmt::Display for NoiseSweep {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for NoiseSweep {
    type Err = SweepError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        NoiseSweep::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| SweepError::UnknownSweep(s.to_owned()))
    }
}
