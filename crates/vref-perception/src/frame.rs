//! One camera frame as the front end takes it.

use image::{GrayImage, ImageBuffer, Luma, RgbImage};

use crate::{FrameError, Intrinsics};

/// 16-bit depth readings along the optical axis (0: no reading).
pub type DepthPixels = ImageBuffer<Luma<u16>, Vec<u16>>;

/// Farthest a depth reading may say, metres: a scale that puts the
/// deepest reading (65535 units) beyond it is a wrong scale, and would
/// give coordinates no scene has.
pub const MAX_DEPTH_M: f64 = 1000.0;

/// A depth image and what one unit of it is in metres.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthImage {
    pixels: DepthPixels,
    metres_per_unit: f64,
}

impl DepthImage {
    /// `metres_per_unit` must be positive and put the deepest reading
    /// within [`MAX_DEPTH_M`] (BOP: its `depth_scale` / 1000, readings
    /// being millimetres times the scale).
    pub fn new(pixels: DepthPixels, metres_per_unit: f64) -> Result<Self, FrameError> {
        let deepest = metres_per_unit * f64::from(u16::MAX);
        if !(metres_per_unit > 0.0 && deepest <= MAX_DEPTH_M) {
            return Err(FrameError::BadDepthScale {
                value: metres_per_unit,
            });
        }
        Ok(Self {
            pixels,
            metres_per_unit,
        })
    }

    pub fn pixels(&self) -> &DepthPixels {
        &self.pixels
    }

    pub fn metres_per_unit(&self) -> f64 {
        self.metres_per_unit
    }
}

/// One object's instance mask: non-zero pixels are the object.
#[derive(Debug, Clone, Copy)]
pub struct Mask<'a> {
    /// The id the object is reported under (e.g. a tracker's track id).
    pub id: u64,
    pub pixels: &'a GrayImage,
}

/// A colour image, its depth image (registered to it: the same pixel sees
/// the same point), the camera's intrinsics and the segmenter's masks.
#[derive(Debug, Clone, Copy)]
pub struct Frame<'a> {
    pub colour: &'a RgbImage,
    pub depth: &'a DepthImage,
    pub intrinsics: Intrinsics,
    pub masks: &'a [Mask<'a>],
}

impl Frame<'_> {
    /// Every image must have the colour image's size.
    pub fn check(&self) -> Result<(), FrameError> {
        let (width, height) = self.colour.dimensions();
        if width == 0 || height == 0 {
            return Err(FrameError::Empty);
        }
        let (dw, dh) = self.depth.pixels.dimensions();
        if (dw, dh) != (width, height) {
            return Err(FrameError::DepthSize {
                width,
                height,
                found_width: dw,
                found_height: dh,
            });
        }
        for mask in self.masks {
            let (mw, mh) = mask.pixels.dimensions();
            if (mw, mh) != (width, height) {
                return Err(FrameError::MaskSize {
                    id: mask.id,
                    width,
                    height,
                    found_width: mw,
                    found_height: mh,
                });
            }
        }
        Ok(())
    }
}
