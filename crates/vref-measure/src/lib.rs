//! How vref states what it measured, the same in every crate, binary and
//! test: [`percentile`] is the one percentile definition (nearest rank),
//! [`duration`] the one way a duration is written on a command line
//! (`10s`, `500ms`), [`direction`] the one way a direction is (`0,0,1`).
//! Nothing here touches IPC or the file system, so the lowest crates
//! (vref-match's bench) can use it too.

pub mod direction;
pub mod duration;
pub mod percentile;

pub use direction::{DirectionError, parse_direction};
pub use duration::{DurationError, format_duration, parse_duration};
pub use percentile::{nearest_rank, percentile, percentile_of};
