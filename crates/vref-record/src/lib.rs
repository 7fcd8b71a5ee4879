//! Recordings of what the feeds published, to replay later as a feed
//! source, in one of two formats, told apart by their first bytes:
//!
//! - **MCAP** (`.mcap`), written by `vref record --out FILE.mcap` and
//!   `vref view --mcap FILE` (crate vref-view, through the Foxglove SDK):
//!   the raw wire messages on their own channels ([`WireChannel`]) beside
//!   Foxglove's; [`read_frames`] reads the raw ones back.
//! - **vref's own** (`.vrec`, [`RecordingWriter`], [`RecordingReader`]):
//!   the magic `VREFREC2` followed by frames, each a little-endian `u32`
//!   length and that many bytes of bincode (standard configuration,
//!   serde). Files that start with `VREFREC1` (before snapshots carried
//!   an up vector) are still read, their snapshots without one.
//!
//! MCAP files written before wire schema 3 hold the shorter snapshot
//! header of schema 2; their channel's schema says so, and they are read
//! as snapshots without an up vector.
//!
//! Frames are in arrival order with their timestamps, so a replay can keep
//! the original pacing. A recording cut short (its recorder killed, its
//! disk full) is read up to its last complete MCAP chunk or frame
//! ([`read_recording`], which says where it stopped).

mod error;
mod frame;
mod mcap_file;
mod partial;
mod reader;
mod wire_channels;
mod writer;

pub use error::RecordError;
pub use frame::{Frame, RecordedObject, RecordedRay, RecordedSnapshot};
pub use mcap_file::{MCAP_MAGIC, mcap_frames, read_frames};
pub use partial::{Cut, Recording, read_recording};
pub use reader::RecordingReader;
pub use wire_channels::{WIRE_ENCODING, WIRE_SCHEMA_ENCODING, WireChannel};
pub use writer::RecordingWriter;

/// First bytes of every recording written in vref's own format.
pub const MAGIC: &[u8; 8] = b"VREFREC2";
/// First bytes of the format's first version, still read.
pub const MAGIC_V1: &[u8; 8] = b"VREFREC1";
/// Largest frame accepted when reading: a corrupt length must not make the
/// reader allocate without bound.
pub const MAX_FRAME_BYTES: u32 = 16 * 1024 * 1024;
