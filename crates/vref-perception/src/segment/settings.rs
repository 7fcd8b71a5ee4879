//! The `[segmentation]` settings: how the class-agnostic segmenter finds
//! the supporting plane and splits what stands on it.

use serde::{Deserialize, Serialize};

use crate::SettingsError;

/// The segmenter's constants (the `[segmentation]` table of vref.toml).
/// Lengths are metres; a length "at 1 m" grows with the square of the
/// depth, as a structured-light or stereo camera's depth noise does.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SegmentationSettings {
    /// The plane is fitted to every `plane_stride`-th pixel of every
    /// `plane_stride`-th row.
    pub plane_stride: u32,
    /// RANSAC hypotheses (three sampled points each).
    pub plane_iterations: u32,
    /// Seed of the RANSAC sampler: the same frame and seed give the same
    /// labels.
    pub plane_seed: u64,
    /// A reading belongs to the plane within this distance of it, at 1 m.
    pub plane_tolerance_m: f64,
    /// The plane must hold at least this share of the sampled readings,
    /// else the frame has no supporting plane.
    pub min_plane_share: f64,
    /// Without an up vector: the plane must be tilted at least this much
    /// (degrees) against the image plane, else it is a wall or a lid seen
    /// face on. A camera looking straight down at its table sets 0.
    pub min_plane_tilt_deg: f64,
    /// With an up vector: the plane's normal must be within this many
    /// degrees of it.
    pub max_up_angle_deg: f64,
    /// A reading this far above the plane starts an object, if its height
    /// averaged over its 3 x 3 neighbourhood is above `plane_tolerance_m`
    /// at its depth divided by 3 (the noise of a mean of nine readings).
    pub min_height_m: f64,
    /// Objects grow back down to readings this far above the plane.
    pub grow_height_m: f64,
    /// Neighbouring readings whose depths differ by more than this share
    /// of their depth lie on different surfaces.
    pub jump_ratio: f64,
    /// Half width (pixels) of the box filter that smooths depth before
    /// normals are taken.
    pub smooth_radius: u32,
    /// Normals are taken from smoothed points this many pixels apart.
    pub normal_step: u32,
    /// Concave crease: normals `crease_step` pixels either side of a pixel
    /// that turn towards each other by more than this (the change of the
    /// unit normal along the unit direction between them; 0.4 is about
    /// 23 degrees) cut it.
    pub crease: f64,
    /// Pixels either side of a pixel whose normals the crease test
    /// compares.
    pub crease_step: u32,
    /// Where the geometry is unsure (a crease of at least `weak_crease`,
    /// or a depth step of at least half `jump_ratio`), a colour edge this
    /// strong cuts too: the mean absolute difference of the R, G, B values
    /// of the pixels either side.
    pub colour_edge: f64,
    /// A crease this strong is weak evidence for `colour_edge` to confirm.
    pub weak_crease: f64,
    /// Segments with fewer pixels are dropped.
    pub min_pixels: u32,
    /// Cut pixels are given back to the neighbouring segment across at
    /// most this many pixels (more at range: as many as the band between
    /// the seed and growth heights spans in the image).
    pub grow_steps: u32,
    /// A segment of at most `merge_max_pixels` joins a neighbour that
    /// holds at least `merge_border` of its outline (across continuous
    /// depth) when their mean colours differ by less than `merge_colour`
    /// (mean absolute R, G, B difference): a piece that a crease inside
    /// one object cut off, not an object of its own. 0 switches it off.
    pub merge_colour: f64,
    /// The share of the small segment's outline the neighbour must hold.
    pub merge_border: f64,
    /// Larger segments never join another.
    pub merge_max_pixels: u32,
    /// The support's smooth warp (a depth scale drifting across the image)
    /// is fitted to the readings within this many `plane_tolerance_m z^2`
    /// of it and its lift taken off the heights; 0 switches it off.
    pub support_warp: f64,
}

impl Default for SegmentationSettings {
    fn default() -> Self {
        Self {
            plane_stride: 4,
            plane_iterations: 200,
            plane_seed: 1,
            plane_tolerance_m: 0.01,
            min_plane_share: 0.2,
            min_plane_tilt_deg: 10.0,
            max_up_angle_deg: 30.0,
            min_height_m: 0.007,
            grow_height_m: 0.003,
            jump_ratio: 0.02,
            smooth_radius: 1,
            normal_step: 3,
            crease: 0.4,
            crease_step: 4,
            colour_edge: 40.0,
            weak_crease: 0.2,
            min_pixels: 200,
            grow_steps: 8,
            merge_colour: 30.0,
            merge_border: 0.2,
            merge_max_pixels: 2000,
            support_warp: 3.0,
        }
    }
}

/// One reading's depth noise at 1 m of the camera the settings were tuned
/// for (OSD's Kinect; the robot camera's `pixel` law has the same).
pub const REFERENCE_PIXEL_NOISE_M: f64 = 0.0025;

impl SegmentationSettings {
    /// The settings for a camera whose one reading errs by `pixel` (its
    /// `[perception.*] pixel` law): a camera noisier at 1 m than the
    /// reference by a factor k gets its depth thresholds (plane tolerance,
    /// heights, jump ratio) and crease thresholds multiplied by sqrt(k), and
    /// its smoothing radius too, so that noise neither seeds nor cuts
    /// objects; a camera as quiet as the reference, or quieter, keeps
    /// them.
    pub fn for_camera(&self, pixel: crate::DepthLaw) -> Self {
        let k = pixel.at(1.0) / REFERENCE_PIXEL_NOISE_M;
        if !(k.is_finite() && k > 1.0) {
            return *self;
        }
        let s = k.sqrt();
        Self {
            plane_tolerance_m: self.plane_tolerance_m * s,
            min_height_m: self.min_height_m * s,
            grow_height_m: self.grow_height_m * s,
            jump_ratio: self.jump_ratio * s,
            smooth_radius: (f64::from(self.smooth_radius) * s).round() as u32,
            crease: self.crease * s,
            weak_crease: self.weak_crease * s,
            ..*self
        }
    }

    pub fn validate(&self) -> Result<(), SettingsError> {
        let bad = |name, value: f64, expected| {
            Err(SettingsError::Bad {
                name,
                value,
                expected,
            })
        };
        let counts = [
            ("segmentation.plane_stride", self.plane_stride, 1, 64),
            (
                "segmentation.plane_iterations",
                self.plane_iterations,
                1,
                100_000,
            ),
            ("segmentation.smooth_radius", self.smooth_radius, 0, 32),
            ("segmentation.normal_step", self.normal_step, 1, 32),
            ("segmentation.crease_step", self.crease_step, 1, 32),
            ("segmentation.min_pixels", self.min_pixels, 1, u32::MAX),
            ("segmentation.grow_steps", self.grow_steps, 0, 255),
        ];
        for (name, value, low, high) in counts {
            if !(low..=high).contains(&value) {
                let expected = match name {
                    "segmentation.plane_stride" => "in 1..=64",
                    "segmentation.plane_iterations" => "in 1..=100000",
                    "segmentation.min_pixels" => "at least 1",
                    "segmentation.grow_steps" => "in 0..=255",
                    "segmentation.smooth_radius" => "in 0..=32",
                    _ => "in 1..=32",
                };
                return bad(name, f64::from(value), expected);
            }
        }
        let positive = [
            ("segmentation.plane_tolerance_m", self.plane_tolerance_m),
            ("segmentation.min_height_m", self.min_height_m),
            ("segmentation.jump_ratio", self.jump_ratio),
            ("segmentation.crease", self.crease),
            ("segmentation.weak_crease", self.weak_crease),
            ("segmentation.colour_edge", self.colour_edge),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return bad(name, value, "positive and finite");
            }
        }
        if !(self.grow_height_m.is_finite()
            && self.grow_height_m >= 0.0
            && self.grow_height_m <= self.min_height_m)
        {
            return bad(
                "segmentation.grow_height_m",
                self.grow_height_m,
                "in [0, min_height_m]",
            );
        }
        if self.weak_crease > self.crease {
            return bad(
                "segmentation.weak_crease",
                self.weak_crease,
                "at most crease",
            );
        }
        if !(self.min_plane_share.is_finite()
            && self.min_plane_share > 0.0
            && self.min_plane_share <= 1.0)
        {
            return bad(
                "segmentation.min_plane_share",
                self.min_plane_share,
                "in (0, 1]",
            );
        }
        if !(self.merge_colour.is_finite() && self.merge_colour >= 0.0) {
            return bad(
                "segmentation.merge_colour",
                self.merge_colour,
                "zero (off) or positive and finite",
            );
        }
        if !(self.support_warp.is_finite() && self.support_warp >= 0.0) {
            return bad(
                "segmentation.support_warp",
                self.support_warp,
                "zero (off) or positive and finite",
            );
        }
        if !(self.merge_border.is_finite() && self.merge_border > 0.0 && self.merge_border <= 1.0) {
            return bad("segmentation.merge_border", self.merge_border, "in (0, 1]");
        }
        for (name, value) in [
            ("segmentation.min_plane_tilt_deg", self.min_plane_tilt_deg),
            ("segmentation.max_up_angle_deg", self.max_up_angle_deg),
        ] {
            if !(value.is_finite() && (0.0..=90.0).contains(&value)) {
                return bad(name, value, "in [0, 90] degrees");
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod camera_tests {
    use super::*;
    use crate::DepthLaw;

    #[test]
    fn a_noisier_camera_gets_coarser_thresholds_and_a_quiet_one_keeps_them() {
        let base = SegmentationSettings::default();
        let quiet = DepthLaw {
            a: 0.0,
            b: 0.0,
            c: 0.001,
        };
        assert_eq!(base.for_camera(quiet), base);
        let four_times = DepthLaw {
            c: 4.0 * REFERENCE_PIXEL_NOISE_M,
            ..quiet
        };
        let coarse = base.for_camera(four_times);
        assert!((coarse.min_height_m - 2.0 * base.min_height_m).abs() < 1e-12);
        assert!((coarse.jump_ratio - 2.0 * base.jump_ratio).abs() < 1e-12);
        assert_eq!(coarse.smooth_radius, 2 * base.smooth_radius);
        assert_eq!(coarse.min_pixels, base.min_pixels);
        assert!(coarse.validate().is_ok());
    }
}
