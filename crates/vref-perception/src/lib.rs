//! The perception front end: a colour image, a registered 16-bit depth
//! image, the camera's intrinsics and a segmenter's instance masks in;
//! objects out, each with a 3D position in the camera frame (OpenCV axes,
//! metres), the standard deviation of that position from the camera's
//! depth-noise law, and an appearance feature (colour and gradient
//! histograms, [`FEATURE_DIM`] long). Pure: no IPC, no printing.
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use std::path::Path;
//! use vref_perception::*;
//!
//! let settings = PerceptionSettings::default();
//! let limit = settings.image_limit();
//! let colour = load_colour(Path::new("rgb/000000.jpg"), limit)?;
//! let depth = DepthImage::new(load_depth(Path::new("depth/000000.png"), limit)?, 0.001)?;
//! let mask = load_mask(Path::new("mask_visib/000000_000000.png"), limit)?;
//! let masks = [Mask { id: 7, pixels: &mask }];
//! let frame = Frame {
//!     colour: &colour,
//!     depth: &depth,
//!     intrinsics: Intrinsics::new(539.0, 539.0, 320.0, 240.0)?,
//!     masks: &masks,
//! };
//! let mut front_end = FrontEnd::new(settings.robot());
//! let mut objects = Vec::new();
//! let skipped = front_end.process(&frame, &mut objects)?;
//! for o in &objects {
//!     println!("object {} at {:?} m, sigma {:?} m", o.id, o.position, o.sigma);
//! }
//! # let _ = skipped;
//! # Ok(())
//! # }
//! ```

mod depth_noise;
mod error;
mod features;
pub mod folder;
mod frame;
mod front_end;
mod intrinsics;
pub mod lens;
mod load;
mod noise;
mod outline;
pub mod reproject;
pub mod segment;
mod settings;

pub use depth_noise::{FrameLaw, NoiseSource, PixelNoise, UnknownNoiseSource, pixel_noise};
pub use error::{FrameError, LoadError, SettingsError};
pub use features::{BoundingBox, COLOUR_DIM, FEATURE_DIM, SHAPE_DIM};
pub use frame::{DepthImage, DepthPixels, Frame, MAX_DEPTH_M, Mask};
pub use front_end::{Detection, FrontEnd, Skipped};
pub use intrinsics::Intrinsics;
pub use lens::{Distortion, DistortionUse, LensError, Rectifier};
pub use load::{ImageLimit, MAX_IMAGE_PIXELS, image_size, load_colour, load_depth, load_mask};
pub use noise::{CameraNoise, DepthLaw};
pub use outline::{outline_polygons, signed_area};
pub use segment::{
    LabelImage, LabelMask, NoSupport, Plane, RgbdFrame, SegmentError, Segmentation,
    SegmentationSettings, Segmenter, label_masks,
};
pub use settings::{FrontEndSettings, PerceptionSettings};
