//! What a depth camera states about its error, and what that makes of
//! the error of an object's position.

use serde::{Deserialize, Serialize};

use crate::SettingsError;

/// `sigma(z) = a + b z + c z^2` in metres, `z` the depth in metres: the
/// form depth datasheets give (stereo and time-of-flight errors grow
/// with z or z^2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DepthLaw {
    pub a: f64,
    pub b: f64,
    pub c: f64,
}

impl DepthLaw {
    pub const ZERO: DepthLaw = DepthLaw {
        a: 0.0,
        b: 0.0,
        c: 0.0,
    };

    pub fn at(&self, z: f64) -> f64 {
        self.a + self.b * z + self.c * z * z
    }

    fn validate(&self, name: &'static str) -> Result<(), SettingsError> {
        for value in [self.a, self.b, self.c] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(SettingsError::Bad {
                    name,
                    value,
                    expected: "finite and not negative (each of a, b, c)",
                });
            }
        }
        Ok(())
    }
}

/// One camera's depth error, in two parts that behave differently under
/// the median over a mask.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraNoise {
    /// Independent noise of one pixel's reading: the median of `n`
    /// readings errs by `sqrt(pi / 2) sigma / sqrt(n)`.
    pub pixel: DepthLaw,
    /// Error shared by neighbouring pixels, which no statistic over one
    /// mask removes: a smooth warp across the image, a wrong depth scale,
    /// calibration.
    pub systematic: DepthLaw,
}

impl CameraNoise {
    pub(crate) fn validate(&self, camera: &'static str) -> Result<(), SettingsError> {
        let (pixel, systematic) = match camera {
            "robot" => ("perception.robot.pixel", "perception.robot.systematic"),
            _ => ("perception.human.pixel", "perception.human.systematic"),
        };
        self.pixel.validate(pixel)?;
        self.systematic.validate(systematic)
    }

    /// Standard deviation of a depth `z` (metres) measured as the median
    /// of `n` pixels' readings.
    pub fn depth_sigma(&self, z: f64, n: usize) -> f64 {
        let n = n.max(1) as f64;
        let median = self.pixel.at(z) * (std::f64::consts::FRAC_PI_2 / n).sqrt();
        median.hypot(self.systematic.at(z))
    }

    /// Per-axis standard deviation of position `p` (camera frame) whose
    /// depth is measured from `n` pixels. A depth error moves the point
    /// along its ray, which scales every coordinate alike: axis `k` errs by
    /// `|p_k| sigma_z / z`, so that the three together are the error along
    /// the ray (`range sigma_z / z`), which is how `rigid` reads them.
    pub fn position_sigma(&self, p: [f64; 3], n: usize) -> [f64; 3] {
        if p[2] <= 0.0 {
            return [0.0; 3];
        }
        let relative = self.depth_sigma(p[2], n) / p[2];
        p.map(|c| c.abs() * relative)
    }
}
