//! The raw wire channels of an MCAP file that vref writes: every message
//! as the services published it (vref-wire's bytes), one channel per
//! service, so that a replay publishes exactly what was recorded. They sit
//! beside the Foxglove channels; Foxglove shows them as opaque bytes.

use vref_wire::bytes::WireBytes;
use vref_wire::{
    DecisionEntry, DecisionHeader, ObjectEntry, PointingRay, SCHEMA_VERSION, SnapshotHeader,
};

/// Message encoding of the raw channels: vref-wire's bytes.
pub const WIRE_ENCODING: &str = "vref-wire";
/// Schema encoding of the raw channels: the layout in words.
pub const WIRE_SCHEMA_ENCODING: &str = "vref-wire-layout";

/// One raw channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WireChannel {
    RobotSnapshot,
    HumanSnapshot,
    Gesture,
    Decision,
}

impl WireChannel {
    pub const ALL: [WireChannel; 4] = [
        WireChannel::RobotSnapshot,
        WireChannel::HumanSnapshot,
        WireChannel::Gesture,
        WireChannel::Decision,
    ];

    pub fn topic(self) -> &'static str {
        match self {
            WireChannel::RobotSnapshot => "/vref/wire/robot/snapshot",
            WireChannel::HumanSnapshot => "/vref/wire/human/snapshot",
            WireChannel::Gesture => "/vref/wire/human/gesture",
            WireChannel::Decision => "/vref/wire/matcher/decision",
        }
    }

    pub fn from_topic(topic: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.topic() == topic)
    }

    /// The schema's name: the wire types it carries.
    pub fn schema_name(self) -> &'static str {
        match self {
            WireChannel::RobotSnapshot | WireChannel::HumanSnapshot => {
                "vref::SnapshotHeader+[vref::ObjectEntry]"
            }
            WireChannel::Gesture => "vref::PointingRay",
            WireChannel::Decision => "vref::DecisionHeader+[vref::DecisionEntry]",
        }
    }

    /// The wire schema version a channel's schema data (its [`Self::layout`]
    /// when written) names, if it names one.
    pub fn schema_version_of(layout: &[u8]) -> Option<u32> {
        let rest = layout.strip_prefix(b"vref wire schema ")?;
        let end = rest.iter().position(|b| !b.is_ascii_digit())?;
        std::str::from_utf8(&rest[..end]).ok()?.parse().ok()
    }

    /// The schema's data: the byte layout, for readers in other languages.
    pub fn layout(self) -> String {
        let intro = format!(
            "vref wire schema {SCHEMA_VERSION}: little-endian, fields in order, no padding \
             (the #[repr(C)] layout of crates/vref-wire/src/messages.rs)\n"
        );
        let body = match self {
            WireChannel::RobotSnapshot | WireChannel::HumanSnapshot => format!(
                "SnapshotHeader ({} bytes): session u64, sequence u64, timestamp_ns u64, \
                 schema_version u32, side u32, object_count u32, feature_dim u32, \
                 frame_name [u8; 32], up [f32; 3], flags u32 (bit 1: up is known)\n\
                 then every entry of the sample's slice, ObjectEntry ({} bytes each): \
                 track_id u64, position [f32; 3], position_sigma [f32; 3], feature [f32; 64]\n",
                SnapshotHeader::SIZE,
                ObjectEntry::SIZE
            ),
            WireChannel::Gesture => format!(
                "PointingRay ({} bytes): session u64, sequence u64, timestamp_ns u64, \
                 origin [f32; 3], direction [f32; 3], cone_half_angle f32, confidence f32, \
                 schema_version u32, reserved u32\n",
                PointingRay::SIZE
            ),
            WireChannel::Decision => format!(
                "DecisionHeader ({} bytes): robot_session u64, robot_sequence u64, \
                 robot_timestamp_ns u64, human_session u64, human_sequence u64, \
                 human_timestamp_ns u64, solved_ns u64, solve_us u64, solve_index u64, \
                 rotation [f32; 9] (row-major, human frame to robot frame), \
                 translation [f32; 3], pair_count u32, flags u32, method [u8; 16], \
                 schema_version u32, reserved u32\n\
                 then every entry of the sample's slice, DecisionEntry ({} bytes each): \
                 human_track_id u64, robot_track_id u64, confidence f32, status u32, \
                 flags u32, reserved u32\n",
                DecisionHeader::SIZE,
                DecisionEntry::SIZE
            ),
        };
        intro + &body
    }
}
