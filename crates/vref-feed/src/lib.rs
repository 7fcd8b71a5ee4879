//! The two feed services' logic: the perception feed publishes the robot
//! camera's view, the gesture feed the headset's view and the person's
//! pointing rays, as iceoryx2 snapshots (vref-wire).
//!
//! A feed's content comes from one of three sources:
//!
//! - **synthetic**: a [`vref_sim::LiveWorld`] from the `[feeds]` preset and
//!   seed. Its state is a function of the time since an epoch, and
//!   snapshots and rays are published on ticks aligned to that epoch, so
//!   two feed processes given the same configuration and flags show one
//!   world, and the same frame number measures the same way in both.
//! - **dataset**: the scene pairs of a JSON Lines dataset, each shown for a
//!   while, chosen by the time since the epoch (so the two feeds agree).
//! - **recording**: a vref recording's frames of this feed, with their
//!   original spacing, looping.
//! - **bop**: the scenes of a BOP dataset measured by the perception
//!   front end, shown in turn like a dataset, with pointing rays from the
//!   headset camera at objects both views measured ([`BopWorld`]).
//! - **rgbd**: a folder of RGB-D frames, each measured at start-up (the
//!   segmenter makes the masks of a frame that has none), shown in turn
//!   like a dataset; no pointing rays.
//! - **rosbag**: a rosbag2 MCAP file's camera topics, measured at start-up
//!   by a [`BagReader`] (vref-ros2's), replayed like a recording.
//!
//! [`Feed::prepare`] checks everything that can be wrong before shared
//! memory is touched ([`SetupError`]); [`Feed::run`] publishes until a
//! termination request ([`RunError`] if IPC fails).

mod args;
mod bop;
mod camera_file;
mod dataset;
pub mod entries;
mod error;
mod feed;
mod noise;
mod publication;
mod replay;
mod rgbd;
mod role;
mod service;
mod synthetic;
mod ticks;

pub use args::{FeedArgs, SourceSpec};
pub use bop::{BopGesture, BopImageSource, BopSceneSource, BopWorld};
pub use camera_file::warn_unread;
pub use error::{EntryError, RunError, SetupError};
pub use feed::{BagReader, BagSnapshot, Feed, MeasuredBag, Published};
pub use noise::frame_law;
pub use publication::{Due, Publication, Ray, Target};
pub use rgbd::RgbdSummary;
pub use role::Role;
pub use service::{FeedError, run_feed, run_feed_with};
pub use synthetic::synthetic_world;
