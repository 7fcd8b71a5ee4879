//! The bridge's own counters, published as JSON on `<prefix>/bridge/stats`
//! and logged, so that what the network sent and what was refused can be
//! watched from anywhere.

use serde::{Deserialize, Serialize};

use crate::intake::StreamCounters;

/// Everything the bridge has done since it started; counters only grow
/// while one bridge process lives.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BridgeStats {
    /// When the bridge started and when these figures were taken,
    /// nanoseconds since the Unix epoch.
    pub started_ns: u64,
    pub taken_ns: u64,
    pub pid: u32,
    pub prefix: String,
    /// The session the bridge publishes headset messages under.
    pub session: u64,
    /// Headset snapshots and rays: received, passed on, refused by reason.
    pub human_snapshot: StreamCounters,
    pub human_gesture: StreamCounters,
    /// Remote queries: received, answered by the matcher, refused.
    pub reference: StreamCounters,
    /// Messages put into the local services or onto the network.
    pub published: Published,
}

/// Publications, by destination.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Published {
    /// Into iceoryx2: headset snapshots and rays.
    pub human_snapshot: u64,
    pub human_gesture: u64,
    /// Onto Zenoh: the robot's state.
    pub robot_snapshot: u64,
    pub matcher_stats: u64,
    pub matcher_decision: u64,
    /// Local messages not published because they failed validation.
    pub invalid_local: u64,
    /// Publications that failed (iceoryx2 or Zenoh errors).
    pub failed: u64,
}

impl BridgeStats {
    pub fn to_json(&self) -> Vec<u8> {
        serde_json::to_vec(self).unwrap_or_default()
    }

    pub fn from_json(bytes: &[u8]) -> Result<Self, crate::CodecError> {
        serde_json::from_slice(bytes).map_err(|e| crate::CodecError::Json {
            what: "bridge statistics",
            message: e.to_string(),
        })
    }
}
