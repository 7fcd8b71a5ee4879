//! Accuracy against sensor noise: the scenes of one configuration
//! generated again with one family of noise knobs scaled by each of a list
//! of factors, every method evaluated at every factor.
//!
//! Every level uses the same seed, and the generator draws the same random
//! values whatever a knob's size (see `random.rs`), so every level shows
//! the same layouts, camera poses and detections and differs only in the
//! scaled errors: a curve compares like with like.

mod noise;
mod run;

pub use noise::{DEFAULT_LEVELS, NoiseSweep};
pub use run::{Sweep, SweepPoint, accuracy_curves};
