//! vref on ROS 2 without a ROS install: camera topics in, markers,
//! answers and a service out, over `ros2-client` (RustDDS), which speaks
//! DDS/RTPS with CDR to ROS 2 nodes on Fast DDS or Cyclone DDS.
//!
//! - [`msg`]: the standard ROS 2 messages used, field for field.
//! - [`decode`]: Image and CameraInfo to the front end's types, with a
//!   typed reason for every message refused.
//! - [`pairing`]: colour, depth and labels paired by header stamp.
//! - [`perceive`]: a frame to a robot snapshot's objects (labels given or
//!   vref's segmenter).
//! - [`markers`], [`answer`]: the decision as a MarkerArray, the headset
//!   pose, the answer as a PointStamped and as the Trigger reply. Pure.
//! - [`cdr`]: CDR as rosbag2 stores it; [`bag`]: a rosbag2 MCAP file as a
//!   camera, through the same decoding, pairing and perception.
//! - [`record`]: the outputs into an MCAP file ROS 2 tools read.
//! - [`run`]: the vref-ros2 process's loop.

pub mod answer;
pub mod bag;
mod bridge;
pub mod cdr;
pub mod decode;
pub mod markers;
mod matcher_side;
pub mod msg;
pub mod pairing;
pub mod perceive;
pub mod record;

pub use bridge::{Counts, Ros2Error, run};
