//! The channels the viewer logs on: Foxglove's well-known schemas for the
//! scene, the transforms and (when the feeds measure images) the cameras'
//! images, JSON for answers, statistics and decisions, and the raw wire
//! messages (MCAP files only).

use std::sync::Arc;

use foxglove::messages::{
    CameraCalibration, CompressedImage, FrameTransforms, ImageAnnotations, SceneUpdate,
};
use foxglove::{Channel, ChannelDescriptor, Context, RawChannel, Schema};
use serde_json::Value;
use vref_record::{WIRE_ENCODING, WIRE_SCHEMA_ENCODING, WireChannel};
use vref_scene::Side;

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
    /// `foxglove.CompressedImage`: the robot camera's colour image.
    pub const ROBOT_IMAGE: &str = "/vref/robot/image";
    /// `foxglove.CameraCalibration` of the robot camera.
    pub const ROBOT_CALIBRATION: &str = "/vref/robot/calibration";
    /// `foxglove.ImageAnnotations`: the robot objects' mask outlines.
    pub const ROBOT_ANNOTATIONS: &str = "/vref/robot/annotations";
    /// The same three for the headset camera.
    pub const HUMAN_IMAGE: &str = "/vref/human/image";
    pub const HUMAN_CALIBRATION: &str = "/vref/human/calibration";
    pub const HUMAN_ANNOTATIONS: &str = "/vref/human/annotations";
}

/// One camera's image channels.
#[derive(Debug)]
pub struct CameraChannels {
    pub image: Channel<CompressedImage>,
    pub calibration: Channel<CameraCalibration>,
    pub annotations: Channel<ImageAnnotations>,
}

impl CameraChannels {
    fn new(ctx: &Arc<Context>, side: Side) -> Self {
        let (image, calibration, annotations) = match side {
            Side::Robot => (
                topic::ROBOT_IMAGE,
                topic::ROBOT_CALIBRATION,
                topic::ROBOT_ANNOTATIONS,
            ),
            Side::Human => (
                topic::HUMAN_IMAGE,
                topic::HUMAN_CALIBRATION,
                topic::HUMAN_ANNOTATIONS,
            ),
        };
        Self {
            image: ctx.channel_builder(image).build(),
            calibration: ctx.channel_builder(calibration).build(),
            annotations: ctx.channel_builder(annotations).build(),
        }
    }

    pub fn has_sinks(&self) -> bool {
        self.image.has_sinks() || self.calibration.has_sinks() || self.annotations.has_sinks()
    }
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
    /// Robot camera, headset camera; only when there are images to show,
    /// so that no empty channels are listed otherwise.
    pub images: Option<[CameraChannels; 2]>,
}

impl Channels {
    pub fn new(ctx: &Arc<Context>, with_images: bool) -> Result<Self, ViewError> {
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
            images: with_images.then(|| {
                [
                    CameraChannels::new(ctx, Side::Robot),
                    CameraChannels::new(ctx, Side::Human),
                ]
            }),
        })
    }

    pub fn camera(&self, side: Side) -> Option<&CameraChannels> {
        let [robot, human] = self.images.as_ref()?;
        Some(match side {
            Side::Robot => robot,
            Side::Human => human,
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
