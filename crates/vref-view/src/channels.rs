//! The channels the viewer logs on: Foxglove's well-known schemas for the
//! scene and the transforms, JSON for answers, statistics and decisions,
//! and the raw wire messages (MCAP files only).

use std::sync::Arc;

use foxglove::messages::{FrameTransforms, SceneUpdate};
use foxglove::{Channel, ChannelDescriptor, Context, RawChannel, Schema};
use serde_json::Value;
use vref_record::{WIRE_ENCODING, WIRE_SCHEMA_ENCODING, WireChannel};

use crate::{ViewError, json};

/// Topics of the Foxglove channels.
pub mod topic {
    /// `foxglove.SceneUpdate`: both views, pairs, ray, answer.
    pub const SCENE: &str = "/vref/scene";
    /// `foxglove.FrameTransforms`: world, robot camera, headset camera.
    pub const TF: &str = "/tf";
    /// JSON `vref.Answer`: the viewer's own latest-gesture query.
    pub const ANSWER: &str = "/vref/answer";
    /// JSON `vref.MatcherStats`.
    pub const STATS: &str = "/vref/matcher/stats";
    /// JSON `vref.Decision`.
    pub const DECISION: &str = "/vref/matcher/decision";
}

/// Whether a channel is one of the raw wire channels, which only MCAP
/// files get (a live Foxglove could not decode them).
pub fn is_wire(channel: &ChannelDescriptor) -> bool {
    channel.message_encoding() == WIRE_ENCODING
}

#[derive(Debug)]
pub struct Channels {
    pub scene: Channel<SceneUpdate>,
    pub tf: Channel<FrameTransforms>,
    pub answer: Arc<RawChannel>,
    pub stats: Arc<RawChannel>,
    pub decision: Arc<RawChannel>,
    /// In [`WireChannel::ALL`] order.
    pub wire: [Arc<RawChannel>; 4],
}

impl Channels {
    pub fn new(ctx: &Arc<Context>) -> Result<Self, ViewError> {
        let json_channel = |topic: &str, schema: Value| {
            let name = schema["title"].as_str().unwrap_or(topic).to_owned();
            let data = serde_json::to_vec(&schema).unwrap_or_default();
            ctx.channel_builder(topic)
                .message_encoding("json")
                .schema(Schema::new(name, "jsonschema", data))
                .build_raw()
                .map_err(ViewError::foxglove(format!("channel {topic}")))
        };
        let wire_channel = |c: WireChannel| {
            ctx.channel_builder(c.topic())
                .message_encoding(WIRE_ENCODING)
                .schema(Schema::new(
                    c.schema_name(),
                    WIRE_SCHEMA_ENCODING,
                    c.layout().into_bytes(),
                ))
                .build_raw()
                .map_err(ViewError::foxglove(format!("channel {}", c.topic())))
        };
        let [a, b, c, d] = WireChannel::ALL;
        Ok(Self {
            scene: ctx.channel_builder(topic::SCENE).build(),
            tf: ctx.channel_builder(topic::TF).build(),
            answer: json_channel(topic::ANSWER, json::answer_schema())?,
            stats: json_channel(topic::STATS, json::stats_schema())?,
            decision: json_channel(topic::DECISION, json::decision_schema())?,
            wire: [
                wire_channel(a)?,
                wire_channel(b)?,
                wire_channel(c)?,
                wire_channel(d)?,
            ],
        })
    }

    pub fn wire(&self, channel: WireChannel) -> &RawChannel {
        let [robot, human, gesture, decision] = &self.wire;
        match channel {
            WireChannel::RobotSnapshot => robot,
            WireChannel::HumanSnapshot => human,
            WireChannel::Gesture => gesture,
            WireChannel::Decision => decision,
        }
    }
}
