//! What the matcher decides, for Foxglove: vref's wire messages turned
//! into Foxglove's own schemas, served live over the Foxglove WebSocket
//! protocol and written to MCAP files (docs/viewer.md).
//!
//! - [`scene()`] draws both views' objects coloured by the matcher's
//!   decision ([`Outcome`]), track ids, lines between matched pairs, the
//!   pointing ray and the latest answer as one `foxglove.SceneUpdate`;
//!   [`transforms`] places the cameras (`foxglove.FrameTransforms`): the
//!   headset by the matcher's estimated motion when there is one, beside
//!   the robot's view otherwise. Both are pure.
//! - [`json`] holds the answers, statistics and decisions as JSON.
//! - [`run`] is the viewer process's loop: subscribers only (latest wins),
//!   plus an optional low-rate latest-gesture query of its own.
//!
//! - [`images`] holds the cameras' images when the feeds measure images:
//!   `foxglove.CompressedImage`, `foxglove.CameraCalibration` and the
//!   masks' outlines as `foxglove.ImageAnnotations`, pure;
//!   [`load_bop_images`] reads them from the BOP dataset the feeds show.

mod bop;
mod channels;
mod error;
mod frames;
mod geometry;
pub mod images;
pub mod json;
mod live;
mod scene;
mod state;

pub use bop::{ImagesError, load_bop_images};
pub use channels::{Channels, is_wire, topic};
pub use error::ViewError;
pub use frames::{FrameNames, HUMAN_FRAME, Placement, ROBOT_FRAME, WORLD_FRAME, transforms};
pub use geometry::{quaternion_of, rotate, rotation_between};
pub use live::{Counts, Started, ViewOptions, run};
pub use scene::{Outcome, entity, marker_size, scene};
pub use state::{Asked, Latest, View};
