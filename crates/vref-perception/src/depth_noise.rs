//! The per-reading depth noise a frame shows, measured on the frame
//! itself: for a camera that states none, or whose statement is another
//! camera's (the configured headset's, for two photos of one's own).

use serde::{Deserialize, Serialize};

use crate::{DepthImage, DepthLaw};

/// Neighbouring readings further apart than this share of their depth lie
/// on two surfaces (an outline), not one noisy one.
const SAME_SURFACE: f64 = 0.15;
/// The share of second differences kept, smallest first: the rest are
/// creases, texture in depth and what `SAME_SURFACE` let through.
const KEPT: f64 = 0.9;
/// The second moment of a standard normal cut to its central `KEPT`
/// (`1 - 2 a phi(a) / KEPT`, `a` its 0.95 quantile): what scales the kept
/// moment back to the whole variance.
const KEPT_MOMENT: f64 = 0.6230;
/// Fewest second differences a measurement rests on.
const MIN_SAMPLES: usize = 1000;

/// What [`pixel_noise`] measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelNoise {
    /// `c` of `sigma = c z^2` (metres, `z` in metres): one reading's
    /// independent noise, as [`crate::DepthLaw`]'s `c`.
    pub c: f64,
    /// Second differences it rests on.
    pub samples: usize,
}

impl PixelNoise {
    /// The measurement as a depth law: `sigma = c z^2`.
    pub fn law(&self) -> DepthLaw {
        DepthLaw {
            a: 0.0,
            b: 0.0,
            c: self.c,
        }
    }
}

/// The per-reading noise `depth` shows, as `c` of `sigma = c z^2` (the
/// law of structured-light and stereo cameras): from the second
/// differences of three neighbouring readings along rows and columns,
/// `z[k-1] - 2 z[k] + z[k+1]`, which cancel a surface's slope (a plane's
/// depth curves across three pixels by far less than any camera's noise)
/// and leave `6 sigma^2` of independent noise, and none of a smooth warp
/// or a wrong depth scale. Each is divided by `z[k]^2`; their spread is
/// the root of the kept second moment ([`KEPT`]), scaled to the whole
/// ([`KEPT_MOMENT`]). `None` with fewer than [`MIN_SAMPLES`] readings in
/// threes on one surface (a frame almost without depth).
pub fn pixel_noise(depth: &DepthImage) -> Option<PixelNoise> {
    let pixels = depth.pixels();
    let (width, height) = (pixels.width() as usize, pixels.height() as usize);
    let scale = depth.metres_per_unit();
    let raw = pixels.as_raw();
    let at = |x: usize, y: usize| f64::from(raw[y * width + x]) * scale;
    let mut ratios = Vec::new();
    let mut second = |a: f64, b: f64, c: f64| {
        let limit = SAME_SURFACE * b;
        if a > 0.0 && b > 0.0 && c > 0.0 && (a - b).abs() <= limit && (c - b).abs() <= limit {
            ratios.push(((a - 2.0 * b + c) / (b * b)).abs());
        }
    };
    for y in 0..height {
        for x in 1..width.saturating_sub(1) {
            second(at(x - 1, y), at(x, y), at(x + 1, y));
        }
    }
    for y in 1..height.saturating_sub(1) {
        for x in 0..width {
            second(at(x, y - 1), at(x, y), at(x, y + 1));
        }
    }
    if ratios.len() < MIN_SAMPLES {
        return None;
    }
    let kept = ((ratios.len() as f64 * KEPT) as usize).max(1);
    let (smallest, _, _) = ratios.select_nth_unstable_by(kept - 1, f64::total_cmp);
    let moment = (smallest.iter().map(|r| r * r).sum::<f64>()
        + ratios[kept - 1] * ratios[kept - 1])
        / kept as f64;
    Some(PixelNoise {
        c: (moment / KEPT_MOMENT / 6.0).sqrt(),
        samples: ratios.len(),
    })
}

/// Where a camera's per-reading depth noise is taken from, for the
/// segmenter's thresholds and the objects' stated errors, wherever vref
/// measures frames of a camera the configuration may not describe (`vref
/// match`, `vref segment`, the feeds' `rgbd:` and `rosbag:` sources,
/// vref-ros2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NoiseSource {
    /// Measured on the camera's frame ([`pixel_noise`]); the configured
    /// law where the frame shows too little depth.
    #[default]
    Frame,
    /// The configured law (`[perception.robot]` or `[perception.human]`
    /// `pixel`).
    Config,
}

impl NoiseSource {
    pub const NAMES: [&'static str; 2] = ["frame", "config"];

    pub fn name(self) -> &'static str {
        match self {
            NoiseSource::Frame => "frame",
            NoiseSource::Config => "config",
        }
    }
}

impl std::fmt::Display for NoiseSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A noise source that is neither `frame` nor `config`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0:?} is not a noise source (frame or config)")]
pub struct UnknownNoiseSource(pub String);

impl std::str::FromStr for NoiseSource {
    type Err = UnknownNoiseSource;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "frame" => Ok(NoiseSource::Frame),
            "config" => Ok(NoiseSource::Config),
            _ => Err(UnknownNoiseSource(s.to_owned())),
        }
    }
}

/// The per-reading law one frame is measured with, and where it came
/// from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrameLaw {
    /// Configured (`NoiseSource::Config`).
    Configured(DepthLaw),
    /// Measured on the frame: `sigma = c z^2`.
    Measured(PixelNoise),
    /// Asked to measure, but the frame shows too little depth: the
    /// configured law.
    Unmeasured(DepthLaw),
}

impl FrameLaw {
    /// The law for `depth` of a camera configured with `configured`.
    pub fn of(source: NoiseSource, depth: &DepthImage, configured: DepthLaw) -> Self {
        match source {
            NoiseSource::Config => FrameLaw::Configured(configured),
            NoiseSource::Frame => {
                pixel_noise(depth).map_or(FrameLaw::Unmeasured(configured), FrameLaw::Measured)
            }
        }
    }

    pub fn law(&self) -> DepthLaw {
        match *self {
            FrameLaw::Configured(law) | FrameLaw::Unmeasured(law) => law,
            FrameLaw::Measured(m) => m.law(),
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::{FrameLaw, NoiseSource, pixel_noise};
    use crate::{DepthImage, DepthLaw, DepthPixels};

    /// Metres per depth unit: fine enough that rounding adds nothing.
    const UNIT: f64 = 0.0001;

    struct Normal(u64);

    impl Normal {
        fn uniform(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        }

        fn sample(&mut self) -> f64 {
            let (u, v) = (self.uniform(), self.uniform());
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        }
    }

    /// A 320 x 240 view of a table tilted away (0.7 to 1.3 m), `surface`
    /// adding to its depth, read with noise `c z^2`.
    fn frame(c: f64, surface: impl Fn(u32, u32, f64) -> f64) -> DepthImage {
        let mut noise = Normal(0x9e37_79b9_7f4a_7c15);
        let pixels = DepthPixels::from_fn(320, 240, |x, y| {
            let z = surface(x, y, 0.7 + 0.6 * f64::from(y) / 240.0);
            let read = z + c * z * z * noise.sample();
            image::Luma([(read / UNIT).round() as u16])
        });
        DepthImage::new(pixels, UNIT).unwrap()
    }

    fn measured(depth: &DepthImage) -> f64 {
        pixel_noise(depth).expect("enough depth").c
    }

    /// The noise is recovered within 5 % across the range of cameras,
    /// from a quiet robot camera to a noisy headset.
    #[test]
    fn the_noise_of_a_plane_is_recovered() {
        for c in [0.001, 0.0025, 0.01, 0.03] {
            let got = measured(&frame(c, |_, _, z| z));
            assert!((got / c - 1.0).abs() < 0.05, "c {c}: measured {got}");
        }
    }

    /// A smooth warp and a wrong depth scale, which every reading of a
    /// neighbourhood shares, are not per-reading noise; objects' outlines
    /// (10 cm steps) are left out.
    #[test]
    fn warps_and_outlines_are_not_noise() {
        let c = 0.0025;
        let warped = measured(&frame(c, |x, _, z| {
            1.02 * z * (1.0 + 0.05 * (f64::from(x) / 60.0).sin())
        }));
        assert!((warped / c - 1.0).abs() < 0.05, "warped: {warped}");
        let boxes = measured(&frame(c, |x, y, z| {
            if (x / 40 + y / 40) % 2 == 0 {
                z - 0.1
            } else {
                z
            }
        }));
        assert!((boxes / c - 1.0).abs() < 0.1, "boxes: {boxes}");
    }

    /// A frame almost without depth gives no measurement, not a guess.
    #[test]
    fn too_little_depth_is_no_measurement() {
        let empty = DepthImage::new(DepthPixels::new(320, 240), UNIT).unwrap();
        assert_eq!(pixel_noise(&empty), None);
        let speck = DepthPixels::from_fn(320, 240, |x, y| {
            image::Luma([if x < 20 && y < 20 { 10_000 } else { 0 }])
        });
        assert_eq!(pixel_noise(&DepthImage::new(speck, UNIT).unwrap()), None);
    }

    /// `frame` measures, `config` keeps the configured law, and a frame
    /// without depth falls back to it; the names read back.
    #[test]
    fn a_frames_law_is_measured_or_configured() {
        let configured = DepthLaw {
            a: 0.001,
            b: 0.0,
            c: 0.02,
        };
        let noisy = frame(0.0025, |_, _, z| z);
        let measured = FrameLaw::of(NoiseSource::Frame, &noisy, configured);
        assert!(matches!(measured, FrameLaw::Measured(_)), "{measured:?}");
        let law = measured.law();
        assert!(
            (law.c / 0.0025 - 1.0).abs() < 0.05 && law.a == 0.0,
            "{law:?}"
        );
        let kept = FrameLaw::of(NoiseSource::Config, &noisy, configured);
        assert_eq!(kept, FrameLaw::Configured(configured));
        let empty = DepthImage::new(DepthPixels::new(320, 240), UNIT).unwrap();
        let fallback = FrameLaw::of(NoiseSource::Frame, &empty, configured);
        assert_eq!(fallback, FrameLaw::Unmeasured(configured));
        assert_eq!(fallback.law(), configured);
        for name in NoiseSource::NAMES {
            assert_eq!(name.parse::<NoiseSource>().unwrap().name(), name);
        }
        assert!("kinect".parse::<NoiseSource>().is_err());
    }
}
