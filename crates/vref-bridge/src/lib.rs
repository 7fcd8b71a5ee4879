//! The network edge of vref: what `vref-bridge` needs to join a robot's
//! iceoryx2 services to a Zenoh network, and what a remote controller
//! needs to ask that robot.
//!
//! - [`format`], [`json`], [`binary`]: the two encodings of every bridged
//!   message, as declared in Zenoh's encoding field.
//! - [`intake`]: what is let in from the network (size, encoding, session,
//!   rate, then vref-wire's validation), counted by reason.
//! - [`keys`]: one robot's Zenoh keys under its prefix (fleet naming).
//! - [`net`]: Zenoh sessions from the settings, and [`net::RemoteClient`].
//! - [`echo`]: a queryable with no matcher behind it, Zenoh's own floor.
//! - [`run`]: the `vref-bridge` process's loop, as the matcher's is in
//!   vref-serve and the feeds' in vref-feed: one thread for each direction
//!   (`headset_in`, `queries_in`, `state_out`) around what they share
//!   (`shared`: the intake and the counters), watched by `workers`.
//!
//! Everything but [`net`], [`echo`] and the loop is pure and tested
//! without a network; the loop is tested on loopback (tests/loopback.rs).

pub mod binary;
pub mod echo;
mod error;
pub mod format;
mod headset_in;
pub mod intake;
pub mod json;
pub mod keys;
pub mod net;
mod queries_in;
pub mod rate;
mod service;
mod shared;
mod state_out;
pub mod stats;
mod workers;

pub use error::{BridgeError, CodecError, NetError};
pub use format::{Format, Message};
pub use intake::{HeadsetIntake, IntakeLimits, QueryIntake, Refusal, StreamCounters};
pub use keys::Keys;
pub use net::{
    ErrorReply, RemoteClient, open_bridge_session, open_client_session, open_peer_session,
    zenoh_config,
};
pub use service::{run, run_until};
pub use stats::{BridgeStats, Published};

/// A session id that differs between runs of the bridge: the start time
/// mixed with the process id, through the splitmix64 finaliser so that
/// close start times give unrelated ids.
pub fn new_session(now_ns: u64, pid: u32) -> u64 {
    let mut z = (now_ns ^ (u64::from(pid) << 40)).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
