//! The `[perception]` settings: what the front end keeps, how it places
//! an object, and each camera's depth error.

use serde::{Deserialize, Serialize};

use crate::{CameraNoise, DepthLaw, ImageLimit, MAX_IMAGE_PIXELS, SettingsError};

/// Largest `max_image_pixels` accepted: a bigger cap would let one 16-bit
/// image take 8 GiB.
const MOST_IMAGE_PIXELS: u64 = 1 << 32;

/// The front end's constants for both cameras (the `[perception]` table
/// of vref.toml).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PerceptionSettings {
    /// Masks with fewer pixels, or fewer pixels with a depth reading, are
    /// skipped (counted): too few to place or describe an object.
    pub min_pixels: usize,
    /// The convex-object correction: an object's centre lies behind its
    /// visible surface by this share of its radius, the radius taken as
    /// that of a disc of the mask's area at the measured depth. A sphere's
    /// median surface depth is 1/sqrt(2) of its radius in front of its
    /// centre; 0 reports the visible surface.
    pub centre_offset: f64,
    /// Most pixels (width x height) an image may have, from a file or a
    /// message: checked against its header before a pixel is decoded.
    pub max_image_pixels: u64,
    pub robot: CameraNoise,
    pub human: CameraNoise,
}

impl Default for PerceptionSettings {
    fn default() -> Self {
        Self {
            min_pixels: 150,
            centre_offset: std::f64::consts::FRAC_1_SQRT_2,
            max_image_pixels: MAX_IMAGE_PIXELS,
            robot: CameraNoise {
                pixel: DepthLaw {
                    c: 0.0025,
                    ..DepthLaw::ZERO
                },
                systematic: DepthLaw {
                    b: 0.005,
                    ..DepthLaw::ZERO
                },
            },
            human: CameraNoise {
                pixel: DepthLaw {
                    c: 0.02,
                    ..DepthLaw::ZERO
                },
                systematic: DepthLaw {
                    b: 0.06,
                    ..DepthLaw::ZERO
                },
            },
        }
    }
}

impl PerceptionSettings {
    pub fn validate(&self) -> Result<(), SettingsError> {
        if self.min_pixels == 0 {
            return Err(SettingsError::Bad {
                name: "perception.min_pixels",
                value: 0.0,
                expected: "at least 1",
            });
        }
        if !(self.centre_offset.is_finite() && (0.0..=2.0).contains(&self.centre_offset)) {
            return Err(SettingsError::Bad {
                name: "perception.centre_offset",
                value: self.centre_offset,
                expected: "in [0, 2]",
            });
        }
        if !(1..=MOST_IMAGE_PIXELS).contains(&self.max_image_pixels) {
            return Err(SettingsError::Bad {
                name: "perception.max_image_pixels",
                value: self.max_image_pixels as f64,
                expected: "at least 1 and at most 2^32 (65536 x 65536)",
            });
        }
        self.robot.validate("robot")?;
        self.human.validate("human")
    }

    /// The size cap every image input is checked against.
    pub fn image_limit(&self) -> ImageLimit {
        ImageLimit {
            max_pixels: self.max_image_pixels,
        }
    }

    /// The front end's settings for the robot camera.
    pub fn robot(&self) -> FrontEndSettings {
        self.camera(self.robot)
    }

    /// The front end's settings for the headset camera.
    pub fn human(&self) -> FrontEndSettings {
        self.camera(self.human)
    }

    fn camera(&self, noise: CameraNoise) -> FrontEndSettings {
        FrontEndSettings {
            min_pixels: self.min_pixels,
            centre_offset: self.centre_offset,
            noise,
        }
    }
}

/// What one camera's front end runs with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrontEndSettings {
    pub min_pixels: usize,
    pub centre_offset: f64,
    pub noise: CameraNoise,
}
