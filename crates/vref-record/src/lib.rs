//! Recordings of what the feeds published, to replay later as a feed
//! source. A file is the magic `VREFREC1` followed by frames, each a
//! little-endian `u32` length and that many bytes of bincode (standard
//! configuration, serde). Frames are in publication order with their
//! timestamps, so a replay can keep the original pacing.

mod error;
mod frame;
mod reader;
mod writer;

pub use error::RecordError;
pub use frame::{Frame, RecordedObject, RecordedRay, RecordedSnapshot};
pub use reader::RecordingReader;
pub use writer::RecordingWriter;

/// First bytes of every recording.
pub const MAGIC: &[u8; 8] = b"VREFREC1";
/// Largest frame accepted when reading: a corrupt length must not make the
/// reader allocate without bound.
pub const MAX_FRAME_BYTES: u32 = 16 * 1024 * 1024;
