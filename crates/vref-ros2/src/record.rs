//! vref's ROS 2 outputs into an MCAP file that ROS 2 tools read
//! (`vref record --ros2`): the MCAP profile `ros2`, each topic's schema
//! in `ros2msg` encoding (the interface definitions, as rosbag2 stores
//! them), each message CDR (message encoding `cdr`), so that `ros2 bag
//! play`, Foxglove and the `rosbags` package read it as a rosbag2 file.
//!
//! The topics are vref-ros2's outputs, made by the same functions:
//! MarkerArray (`[ros2] markers_topic`), the referenced object's
//! PointStamped (`referenced_object_topic`) and the headset pose's
//! PoseStamped (`headset_pose_topic`), from the matcher's snapshots,
//! decisions and latest-gesture answers over iceoryx2; no DDS is started.

use std::collections::BTreeMap;
use std::io::{Seek, Write};
use std::time::{Duration, Instant};

use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use serde::Serialize;
use vref_config::Config;
use vref_scene::Side;
use vref_view::{Asked, View};
use vref_wire::ipc::{IpcError, ReferenceClient, create_node, drain, nap, now_ns, open_snapshot};
use vref_wire::{ObjectEntry, SnapshotHeader};

use crate::answer::{NewAnswers, referenced_point};
use crate::cdr::{CdrError, to_cdr};
use crate::markers::{Frames, Scene, headset_pose, markers};
use crate::matcher_side::MatcherSide;
use crate::msg::{MarkerArray, PointStamped, PoseStamped, Time};

/// The interface definitions, as rosbag2 writes them: the type's own
/// `.msg` text, then each type it uses after a line of 80 `=` and `MSG:
/// package/Type` (generated from ROS 2 Kilted's definitions by `rosbags`
/// 0.11.9, `Typestore.generate_msgdef(.., ros_version=2)`).
pub const MARKER_ARRAY_MSG: &str = include_str!("schemas/MarkerArray.msg");
pub const POINT_STAMPED_MSG: &str = include_str!("schemas/PointStamped.msg");
pub const POSE_STAMPED_MSG: &str = include_str!("schemas/PoseStamped.msg");

/// Longest sleep between turns.
const TURN: Duration = Duration::from_millis(5);

/// Why recording stopped.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    #[error("writing the MCAP file")]
    Mcap(#[from] mcap::McapError),
    #[error("encoding a message")]
    Cdr(#[from] CdrError),
    #[error("iceoryx2")]
    Ipc(#[from] IpcError),
    #[error("{0} must be positive and finite")]
    Rate(&'static str),
}

/// Messages written, by topic kind.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RecordCounts {
    pub marker_arrays: u64,
    pub referenced: u64,
    pub headset_poses: u64,
    /// Latest-gesture questions that got no answer in time.
    pub unanswered: u64,
}

/// QoS as rosbag2 stores it with a channel (`offered_qos_profiles`), for
/// `ros2 bag play` to offer again: reliable, keep last 1, and durability
/// as vref-ros2 publishes the topic.
fn qos(transient_local: bool) -> String {
    let forever = "\n    sec: 9223372036\n    nsec: 854775807";
    format!(
        "- history: keep_last\n  depth: 1\n  reliability: reliable\n  durability: {}\n  deadline:{forever}\n  lifespan:{forever}\n  liveliness: automatic\n  liveliness_lease_duration:{forever}\n  avoid_ros_namespace_conventions: false",
        if transient_local {
            "transient_local"
        } else {
            "volatile"
        }
    )
}

/// An MCAP file of ROS 2 messages on vref-ros2's three output topics.
pub struct Ros2Mcap<W: Write + Seek> {
    writer: mcap::Writer<W>,
    markers: u16,
    point: u16,
    pose: u16,
    sequence: u32,
}

impl<W: Write + Seek> std::fmt::Debug for Ros2Mcap<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ros2Mcap")
            .field("sequence", &self.sequence)
            .finish_non_exhaustive()
    }
}

/// The three topic names.
#[derive(Debug, Clone, Copy)]
pub struct OutputTopics<'a> {
    pub markers: &'a str,
    pub referenced_object: &'a str,
    pub headset_pose: &'a str,
}

impl<W: Write + Seek> Ros2Mcap<W> {
    /// Starts the file: header (profile `ros2`), schemas and channels.
    pub fn new(w: W, topics: OutputTopics<'_>) -> Result<Self, RecordError> {
        let mut writer = mcap::WriteOptions::new()
            .profile("ros2")
            .compression(Some(mcap::Compression::Zstd))
            .create(w)?;
        let mut channel = |name: &str, definition: &str, topic: &str, latched: bool| {
            let schema = writer.add_schema(name, "ros2msg", definition.as_bytes())?;
            let metadata = BTreeMap::from([("offered_qos_profiles".to_owned(), qos(latched))]);
            writer.add_channel(schema, topic, "cdr", &metadata)
        };
        let markers = channel(
            "visualization_msgs/msg/MarkerArray",
            MARKER_ARRAY_MSG,
            topics.markers,
            false,
        )?;
        let point = channel(
            "geometry_msgs/msg/PointStamped",
            POINT_STAMPED_MSG,
            topics.referenced_object,
            true,
        )?;
        let pose = channel(
            "geometry_msgs/msg/PoseStamped",
            POSE_STAMPED_MSG,
            topics.headset_pose,
            false,
        )?;
        Ok(Self {
            writer,
            markers,
            point,
            pose,
            sequence: 0,
        })
    }

    fn write<T: Serialize>(
        &mut self,
        channel_id: u16,
        message: &T,
        log_time_ns: u64,
    ) -> Result<(), RecordError> {
        let data = to_cdr(message)?;
        self.sequence = self.sequence.wrapping_add(1);
        self.writer.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id,
                sequence: self.sequence,
                log_time: log_time_ns,
                publish_time: log_time_ns,
            },
            &data,
        )?;
        Ok(())
    }

    pub fn markers(&mut self, m: &MarkerArray, log_time_ns: u64) -> Result<(), RecordError> {
        self.write(self.markers, m, log_time_ns)
    }

    pub fn referenced(&mut self, p: &PointStamped, log_time_ns: u64) -> Result<(), RecordError> {
        self.write(self.point, p, log_time_ns)
    }

    pub fn headset_pose(&mut self, p: &PoseStamped, log_time_ns: u64) -> Result<(), RecordError> {
        self.write(self.pose, p, log_time_ns)
    }

    /// Writes the summary and index; the file is complete after this.
    pub fn finish(mut self) -> Result<(), RecordError> {
        self.writer.finish()?;
        Ok(())
    }
}

/// Records vref-ros2's outputs into `w` for `duration` or until SIGINT or
/// SIGTERM, asking the matcher for the latest gesture `answer_rate_hz`
/// times a second (0: never, so no referenced objects). Markers follow
/// `[ros2] marker_rate_hz`, the frames `robot_frame_id` and
/// `headset_frame_id`.
pub fn record<W: Write + Seek>(
    config: &Config,
    w: W,
    duration: Duration,
    answer_rate_hz: f64,
) -> Result<RecordCounts, RecordError> {
    let s = &config.ros2;
    if !(answer_rate_hz.is_finite() && answer_rate_hz >= 0.0) {
        return Err(RecordError::Rate("the answer rate"));
    }
    let mut file = Ros2Mcap::new(
        w,
        OutputTopics {
            markers: &s.markers_topic,
            referenced_object: &s.referenced_object_topic,
            headset_pose: &s.headset_pose_topic,
        },
    )?;
    let ipc = &config.ipc;
    let node = create_node(ipc, &format!("vref-record-ros2-{}", std::process::id()))?;
    let iox = |what: &str| {
        let what = format!("creating {what} subscriber");
        move |e: &dyn std::fmt::Debug| IpcError::Iceoryx {
            what,
            message: format!("{e:?}"),
        }
    };
    let (robot_port, _) = open_snapshot(&node, ipc, Side::Robot)?;
    let robot_sub: Subscriber<ipc::Service, [ObjectEntry], SnapshotHeader> = robot_port
        .subscriber_builder()
        .create()
        .map_err(|e| iox("robot snapshot")(&e))?;
    let mut matcher = MatcherSide::open(&node, ipc)?;
    let mut client = if answer_rate_hz > 0.0 {
        Some(ReferenceClient::connect(
            ipc,
            &format!("vref-record-ros2-client-{}", std::process::id()),
        )?)
    } else {
        None
    };
    let frames = Frames {
        robot: &s.robot_frame_id,
        headset: &s.headset_frame_id,
    };
    let marker_period = Duration::from_secs_f64(1.0 / s.marker_rate_hz);
    let answer_period =
        (answer_rate_hz > 0.0).then(|| Duration::from_secs_f64(1.0 / answer_rate_hz));
    let query_timeout = Duration::from_millis(s.query_timeout_ms);

    let mut counts = RecordCounts::default();
    let mut robot_view: Option<View> = None;
    let mut answer: Option<Asked> = None;
    let mut news = NewAnswers::default();
    let mut scene_changed = false;
    let mut last_markers: Option<Instant> = None;
    let mut next_ask = Instant::now();
    let end = Instant::now() + duration;
    while Instant::now() < end && nap(&node, TURN) {
        let drained = drain::newest(&robot_sub);
        if let Some(e) = &drained.error {
            tracing::warn!("receiving a robot snapshot: {e:?}");
        }
        if let Some(sample) = drained.newest {
            robot_view = Some(View::from_wire(sample.user_header(), sample.payload()));
            scene_changed = true;
        }
        let taken = matcher.take();
        scene_changed |= taken.view || taken.decision;
        if taken.decision {
            let now = now_ns();
            if let Some(pose) = matcher
                .decision
                .as_ref()
                .and_then(|d| headset_pose(d, &s.robot_frame_id, Time::from_ns(now)))
            {
                file.headset_pose(&pose, now)?;
                counts.headset_poses += 1;
            }
        }
        if let (Some(client), Some(period)) = (&mut client, answer_period)
            && Instant::now() >= next_ask
        {
            next_ask = Instant::now() + period;
            let start = Instant::now();
            match client.latest_gesture(query_timeout) {
                Ok(a) => {
                    let asked = Asked {
                        answer: a,
                        round_trip_us: start.elapsed().as_micros() as u64,
                        received_ns: now_ns(),
                    };
                    let now = now_ns();
                    if news.is_new(&asked.answer)
                        && let Some(p) =
                            referenced_point(&asked.answer, &s.robot_frame_id, Time::from_ns(now))
                    {
                        file.referenced(&p, now)?;
                        counts.referenced += 1;
                    }
                    if answer.is_none_or(|old| old.answer != asked.answer) {
                        scene_changed = true;
                    }
                    answer = Some(asked);
                }
                Err(e) => {
                    counts.unanswered += 1;
                    tracing::debug!("latest gesture: {e}");
                }
            }
        }
        if scene_changed && last_markers.is_none_or(|t| t.elapsed() >= marker_period) {
            let scene = Scene {
                robot: robot_view.as_ref(),
                human: matcher.human_view.as_ref(),
                decision: matcher.decision.as_ref(),
                answer: answer.as_ref().map(|a| &a.answer),
            };
            let now = now_ns();
            file.markers(&markers(&scene, frames, Time::from_ns(now)), now)?;
            counts.marker_arrays += 1;
            last_markers = Some(Instant::now());
            scene_changed = false;
        }
    }
    file.finish()?;
    Ok(counts)
}
