//! The vref-ros2 loop: camera topics in, robot snapshots out over
//! iceoryx2; the matcher's decisions and answers out as ROS 2 messages and
//! a Trigger service. One thread: every source is drained on each turn
//! (subscriptions keep one message, iceoryx2 services keep the latest),
//! so nothing queues up behind a slow step.

use std::collections::BTreeMap;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use image::RgbImage;
use ros2_client::{
    Context, ContextOptions, Name, NodeName, NodeOptions, QosProfile, ServiceMapping, Subscription,
    qos::Durability, request_id::RmwRequestId,
};
use vref_config::Config;
use vref_perception::{DepthImage, DistortionUse, ImageLimit, LabelImage};

use vref_scene::Side;
use vref_view::{Asked, View};
use vref_wire::ipc::{
    GesturePublisher, IpcError, IpcSettings, ReferenceClient, SnapshotPublisher, create_node, nap,
    now_ns,
};

use crate::answer::{NewAnswers, referenced_point, trigger_failure, trigger_response};
use crate::decode::{self, CameraModel, DecodeError, Stream};
use crate::markers::{Frames, Scene, headset_pose, markers};
use crate::matcher_side::MatcherSide;
use crate::msg::{self, Time};
use crate::pairing::Pairer;
use crate::perceive::{Perceived, Perception};

/// Longest sleep between turns: bounds the added latency of a frame.
const TURN: Duration = Duration::from_millis(2);
/// How often the counters are logged.
const SUMMARY_EVERY: Duration = Duration::from_secs(10);

/// Why vref-ros2 could not start or stopped.
#[derive(Debug, thiserror::Error)]
pub enum Ros2Error {
    /// `ROS_DOMAIN_ID`, which stands in for `[ros2] domain_id`, is not a
    /// domain; its text is part of this one's, as it was always shown.
    #[error("[ros2] {0}")]
    DomainId(vref_config::BadDomainId),
    #[error("ROS 2 name {name:?}: {message}")]
    Name { name: String, message: String },
    #[error("creating the ROS 2 {what}: {message}")]
    Ros { what: String, message: String },
    #[error("iceoryx2")]
    Ipc(#[from] IpcError),
}

impl vref_logging::exit::Fault for Ros2Error {
    /// The configuration was wrong: its [ros2] settings or a topic name.
    fn is_bad_input(&self) -> bool {
        matches!(self, Ros2Error::DomainId(_) | Ros2Error::Name { .. })
    }
}

fn ros(what: impl Into<String>) -> impl FnOnce(&dyn std::fmt::Debug) -> Ros2Error {
    let what = what.into();
    move |e| Ros2Error::Ros {
        what,
        message: format!("{e:?}"),
    }
}

fn name(full: &str) -> Result<Name, Ros2Error> {
    Name::parse(full).map_err(|e| Ros2Error::Name {
        name: full.to_owned(),
        message: format!("{e:?}"),
    })
}

/// What the bridge did, counted; logged every few seconds and at the end.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Counts {
    pub received: BTreeMap<&'static str, u64>,
    /// Skipped messages and frames by stream (or "frame") and reason.
    pub skipped: BTreeMap<(&'static str, &'static str), u64>,
    /// Images that found no partners in time.
    pub unpaired: u64,
    pub snapshots: u64,
    pub headset_snapshots: u64,
    pub rays: u64,
    pub marker_arrays: u64,
    pub referenced: u64,
    pub headset_poses: u64,
    pub service_calls: u64,
}

impl Counts {
    fn skip(&mut self, stream: &'static str, reason: &'static str, why: &dyn std::fmt::Display) {
        let n = self.skipped.entry((stream, reason)).or_insert(0);
        *n += 1;
        // The first of a kind and then every hundredth: a camera sending
        // a bad encoding at 30 Hz must not flood the log.
        if *n == 1 || (*n).is_multiple_of(100) {
            tracing::warn!(stream, reason, count = *n, "skipped: {why}");
        }
    }

    fn log(&self, message: &str) {
        tracing::info!(
            received = ?self.received,
            skipped = ?self.skipped,
            unpaired = self.unpaired,
            snapshots = self.snapshots,
            headset_snapshots = self.headset_snapshots,
            rays = self.rays,
            marker_arrays = self.marker_arrays,
            referenced = self.referenced,
            headset_poses = self.headset_poses,
            service_calls = self.service_calls,
            "{message}"
        );
    }
}

/// One camera's topics, how its frames pair, and where its snapshots go.
struct Camera {
    side: Side,
    colour: Subscription<msg::Image>,
    depth: Subscription<msg::Image>,
    labels: Option<Subscription<msg::Image>>,
    info: Subscription<msg::CameraInfo>,
    pairer: Pairer<RgbImage, DepthImage, LabelImage>,
    perception: Perception,
    model: Option<CameraModel>,
    /// What the CameraInfo's lens distortion is taken for (`[ros2]`).
    distortion: DistortionUse,
    last_info_ns: Option<u64>,
    publisher: SnapshotPublisher,
    frame_id: String,
}

/// Topic names of one camera.
struct CameraTopics<'a> {
    colour: &'a str,
    depth: &'a str,
    info: &'a str,
    labels: &'a str,
}

/// Counter keys: the stream, and which camera's (the robot's is unmarked).
fn key(side: Side, stream: &'static str) -> &'static str {
    match (side, stream) {
        (Side::Robot, s) => s,
        (Side::Human, "colour") => "headset colour",
        (Side::Human, "depth") => "headset depth",
        (Side::Human, "labels") => "headset labels",
        (Side::Human, "camera_info") => "headset camera_info",
        (Side::Human, _) => "headset frame",
    }
}

impl Camera {
    /// Takes every waiting message, and publishes each frame that pairs up;
    /// the objects of the last one published, if any.
    fn drain(&mut self, counts: &mut Counts, max: ImageLimit) -> Result<Option<View>, Ros2Error> {
        let side = self.side;
        let info_key = key(side, Stream::CameraInfo.name());
        loop {
            match self.info.take() {
                Ok(Some((info, _))) => {
                    *counts.received.entry(info_key).or_insert(0) += 1;
                    let last = &mut self.last_info_ns;
                    let checked = decode::stamp_ns(info.header.stamp).and_then(|stamp| {
                        if let Some(last_ns) = last.filter(|&l| stamp < l) {
                            return Err(DecodeError::Backwards {
                                stamp_ns: stamp,
                                last_ns,
                            });
                        }
                        *last = Some(stamp);
                        decode::camera_model(&info, self.distortion)
                    });
                    match checked {
                        Ok(c) => self.model = Some(c),
                        Err(e) => counts.skip(info_key, e.reason(), &e),
                    }
                }
                Ok(None) => break,
                Err(e) => {
                    counts.skip(info_key, "cdr", &format!("{e:?}"));
                    break;
                }
            }
        }
        for (stream, sub) in [
            (Stream::Colour, Some(&self.colour)),
            (Stream::Depth, Some(&self.depth)),
            (Stream::Labels, self.labels.as_ref()),
        ] {
            let Some(sub) = sub else { continue };
            let k = key(side, stream.name());
            loop {
                let image = match sub.take() {
                    Ok(Some((image, _))) => image,
                    Ok(None) => break,
                    Err(e) => {
                        counts.skip(k, "cdr", &format!("{e:?}"));
                        break;
                    }
                };
                *counts.received.entry(k).or_insert(0) += 1;
                let pairer = &mut self.pairer;
                let pushed = decode::stamp_ns(image.header.stamp).and_then(|stamp| {
                    pairer.check_order(stream, stamp)?;
                    match stream {
                        Stream::Colour => pairer.push_colour(stamp, decode::colour(&image, max)?),
                        Stream::Depth => pairer.push_depth(stamp, decode::depth(&image, max)?),
                        _ => pairer.push_labels(stamp, decode::labels(&image, max)?),
                    }
                });
                if let Err(e) = pushed {
                    counts.skip(k, e.reason(), &e);
                }
            }
        }
        let frame_key = key(side, "frame");
        let mut view = None;
        while let Some(frame) = self.pairer.take() {
            let Some(camera) = self.model else {
                counts.skip(frame_key, "no_camera_info", &"no valid CameraInfo yet");
                continue;
            };
            let (w, h) = frame.colour.dimensions();
            if (camera.width, camera.height) != (0, 0) && (camera.width, camera.height) != (w, h) {
                let e = DecodeError::InfoSize {
                    info_width: camera.width,
                    info_height: camera.height,
                    width: w,
                    height: h,
                };
                counts.skip(frame_key, e.reason(), &e);
                continue;
            }
            match self.perception.process(
                &frame.colour,
                &frame.depth,
                &camera,
                frame.labels.as_ref(),
            ) {
                Ok(Perceived { entries, up }) => {
                    self.publisher.publish(
                        entries.len(),
                        vref_perception::FEATURE_DIM,
                        up,
                        frame.stamp_ns,
                        |i| entries[i],
                    )?;
                    match side {
                        Side::Robot => counts.snapshots += 1,
                        Side::Human => counts.headset_snapshots += 1,
                    }
                    view = Some(View {
                        frame_name: self.frame_id.clone(),
                        sequence: 0,
                        timestamp_ns: frame.stamp_ns,
                        objects: entries
                            .iter()
                            .map(|e| (e.track_id, e.position.map(f64::from)))
                            .collect(),
                        up,
                    });
                }
                Err(e) => counts.skip(frame_key, e.reason(), &vref_logging::with_causes(&e)),
            }
        }
        counts.unpaired = counts.unpaired.max(self.pairer.unpaired);
        Ok(view)
    }
}

/// A pointing pose as a ray: origin the position, direction the pose's x
/// axis (the ROS convention for a pointing frame). `None` for a pose that
/// is not finite or whose quaternion is no rotation.
pub fn ray_of(pose: &msg::Pose) -> Option<([f32; 3], [f32; 3])> {
    let p = pose.position;
    let q = pose.orientation;
    let norm = (q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w).sqrt();
    if !(norm.is_finite() && norm > 1e-9 && [p.x, p.y, p.z].iter().all(|v| v.is_finite())) {
        return None;
    }
    let (x, y, z, w) = (q.x / norm, q.y / norm, q.z / norm, q.w / norm);
    // The first column of the rotation matrix: where the x axis goes.
    let d = [
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y + w * z),
        2.0 * (x * z - w * y),
    ];
    Some(([p.x as f32, p.y as f32, p.z as f32], d.map(|v| v as f32)))
}

/// Who an answer is for.
#[derive(Debug, Clone, Copy)]
enum AskFor {
    /// The periodic ask behind `/vref/referenced_object` and the markers.
    Topic,
    /// A service request, answered with this id.
    Service(RmwRequestId),
}

/// The matcher is asked on a thread of its own, so that a matcher that is
/// slow to answer never holds camera frames back: the loop hands it
/// service requests and takes finished answers, and it asks for the
/// topic every `period` by itself.
struct Asker {
    requests: mpsc::Sender<RmwRequestId>,
    answers: mpsc::Receiver<(AskFor, Result<Asked, String>)>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Asker {
    fn start(ipc: &IpcSettings, period: Duration, timeout: Duration) -> Result<Self, Ros2Error> {
        let (requests, wanted) = mpsc::channel::<RmwRequestId>();
        let (done, answers) = mpsc::channel();
        let (ready_tx, ready) = mpsc::channel();
        let ipc = ipc.clone();
        let thread = std::thread::Builder::new()
            .name("vref-ros2-ask".to_owned())
            .spawn(move || {
                // iceoryx2 ports stay on the thread that made them.
                let mut client = match ReferenceClient::connect(&ipc, "vref-ros2-client") {
                    Ok(c) => {
                        ready_tx.send(Ok(())).ok();
                        c
                    }
                    Err(e) => {
                        ready_tx.send(Err(e)).ok();
                        return;
                    }
                };
                let mut next = Instant::now();
                loop {
                    let wait = next.saturating_duration_since(Instant::now());
                    let who = match wanted.recv_timeout(wait) {
                        Ok(id) => AskFor::Service(id),
                        Err(mpsc::RecvTimeoutError::Timeout) => {
                            next = Instant::now() + period;
                            AskFor::Topic
                        }
                        Err(mpsc::RecvTimeoutError::Disconnected) => return,
                    };
                    let result = ask(&mut client, timeout).map_err(|e| e.to_string());
                    if done.send((who, result)).is_err() {
                        return;
                    }
                }
            })
            .map_err(|e| ros("asking thread")(&e))?;
        match ready.recv() {
            Ok(Ok(())) => {}
            Ok(Err(e)) => return Err(Ros2Error::Ipc(e)),
            Err(_) => {
                return Err(Ros2Error::Ros {
                    what: "asking thread".to_owned(),
                    message: "ended before connecting".to_owned(),
                });
            }
        }
        Ok(Self {
            requests,
            answers,
            thread: Some(thread),
        })
    }
}

impl Drop for Asker {
    fn drop(&mut self) {
        // Closing the request channel ends the thread after its current ask.
        let (closed, _) = mpsc::channel();
        self.requests = closed;
        if let Some(t) = self.thread.take() {
            t.join().ok();
        }
    }
}

/// Runs until SIGINT or SIGTERM.
pub fn run(config: &Config) -> Result<Counts, Ros2Error> {
    let s = &config.ros2;
    let domain = s.effective_domain_id().map_err(Ros2Error::DomainId)?;
    let max = config.perception.image_limit();

    // iceoryx2 first: its node catches SIGINT/SIGTERM for the whole process.
    let ipc = &config.ipc;
    let node = create_node(ipc, "vref-ros2")?;
    node.try_cleanup_dead_nodes();
    let mut matcher = MatcherSide::open(&node, ipc)?;

    let context = Context::with_options(ContextOptions::new().domain_id(domain))
        .map_err(|e| ros("DDS participant")(&e))?;
    let node_name =
        NodeName::new(&s.node_namespace, &s.node_name).map_err(|e| Ros2Error::Name {
            name: format!("{}/{}", s.node_namespace, s.node_name),
            message: format!("{e:?}"),
        })?;
    let mut ros_node = context
        .new_node(node_name, NodeOptions::new().enable_rosout(false))
        .map_err(|e| ros("node")(&e))?;
    // Sensor data: best effort, volatile, keep the latest only. A
    // reliable camera publisher matches it too.
    let sensor = QosProfile::subscription_default();
    let tolerance_ns = (s.stamp_tolerance_ms * 1e6).round() as u64;
    // Markers, answers, poses, the service: reliable, latest wins.
    let reliable = QosProfile::publisher_default();
    let mut make_camera = |side: Side, topics: CameraTopics<'_>, frame_id: &str| {
        let mut image_sub = |topic: &str| -> Result<Subscription<msg::Image>, Ros2Error> {
            let t = ros_node
                .create_topic(&name(topic)?, msg::image_type(), &sensor)
                .map_err(|e| ros(format!("topic {topic}"))(&e))?;
            ros_node
                .create_subscription::<msg::Image>(&t, Some(sensor.clone()))
                .map_err(|e| ros(format!("subscription {topic}"))(&e))
        };
        let colour = image_sub(topics.colour)?;
        let depth = image_sub(topics.depth)?;
        let labels = if topics.labels.is_empty() {
            None
        } else {
            Some(image_sub(topics.labels)?)
        };
        let info_topic = ros_node
            .create_topic(&name(topics.info)?, msg::camera_info_type(), &sensor)
            .map_err(|e| ros(format!("topic {}", topics.info))(&e))?;
        let info = ros_node
            .create_subscription::<msg::CameraInfo>(&info_topic, Some(sensor.clone()))
            .map_err(|e| ros(format!("subscription {}", topics.info))(&e))?;
        let front_end = match side {
            Side::Robot => config.perception.robot(),
            Side::Human => config.perception.human(),
        };
        Ok::<_, Ros2Error>(Camera {
            side,
            pairer: Pairer::new(tolerance_ns, labels.is_some()),
            colour,
            depth,
            labels,
            info,
            perception: Perception::new(
                front_end,
                config.segmentation,
                config.ros2.depth_noise,
                config.scene.capacity,
            ),
            model: None,
            distortion: config.ros2.distortion,
            last_info_ns: None,
            publisher: SnapshotPublisher::new(&node, ipc, side, frame_id)?,
            frame_id: frame_id.to_owned(),
        })
    };
    let mut robot_camera = make_camera(
        Side::Robot,
        CameraTopics {
            colour: &s.colour_topic,
            depth: &s.depth_topic,
            info: &s.camera_info_topic,
            labels: &s.labels_topic,
        },
        &s.robot_frame_id,
    )?;
    let mut headset_camera = if s.headset_camera() {
        Some(make_camera(
            Side::Human,
            CameraTopics {
                colour: &s.headset_colour_topic,
                depth: &s.headset_depth_topic,
                info: &s.headset_camera_info_topic,
                labels: &s.headset_labels_topic,
            },
            &s.headset_frame_id,
        )?)
    } else {
        None
    };
    let mut pointing = if s.pointing_topic.is_empty() {
        None
    } else {
        let t = ros_node
            .create_topic(&name(&s.pointing_topic)?, msg::pose_stamped_type(), &sensor)
            .map_err(|e| ros("pointing topic")(&e))?;
        let sub = ros_node
            .create_subscription::<msg::PoseStamped>(&t, Some(reliable.clone()))
            .map_err(|e| ros("pointing subscription")(&e))?;
        Some((sub, GesturePublisher::new(&node, ipc)?))
    };
    let markers_topic = ros_node
        .create_topic(
            &name(&s.markers_topic)?,
            msg::marker_array_type(),
            &reliable,
        )
        .map_err(|e| ros("markers topic")(&e))?;
    let markers_pub = ros_node
        .create_publisher::<msg::MarkerArray>(&markers_topic, Some(reliable.clone()))
        .map_err(|e| ros("markers publisher")(&e))?;
    // Each answer is published once: transient local keeps the latest for
    // a subscriber that matches later (a restarted listener, or this
    // process restarted and answering before discovery completes).
    let latched = reliable.clone().durability(Durability::TransientLocal);
    let point_topic = ros_node
        .create_topic(
            &name(&s.referenced_object_topic)?,
            msg::point_stamped_type(),
            &latched,
        )
        .map_err(|e| ros("referenced object topic")(&e))?;
    let point_pub = ros_node
        .create_publisher::<msg::PointStamped>(&point_topic, Some(latched.clone()))
        .map_err(|e| ros("referenced object publisher")(&e))?;
    let pose_topic = ros_node
        .create_topic(
            &name(&s.headset_pose_topic)?,
            msg::pose_stamped_type(),
            &reliable,
        )
        .map_err(|e| ros("headset pose topic")(&e))?;
    let pose_pub = ros_node
        .create_publisher::<msg::PoseStamped>(&pose_topic, Some(reliable.clone()))
        .map_err(|e| ros("headset pose publisher")(&e))?;
    // Enhanced: the request/reply mapping Fast DDS and Cyclone DDS use
    // for ROS 2 services (sample identities in the RTPS inline QoS).
    let server = ros_node
        .create_server::<msg::TriggerRequest, msg::TriggerResponse>(
            ServiceMapping::Enhanced,
            &name(&s.latest_gesture_service)?,
            &msg::trigger_type(),
            reliable.clone(),
            reliable.clone(),
        )
        .map_err(|e| ros("latest gesture service")(&e))?;
    tracing::info!(
        domain,
        node = %format!("{}/{}", s.node_namespace.trim_end_matches('/'), s.node_name),
        colour = %s.colour_topic,
        depth = %s.depth_topic,
        camera_info = %s.camera_info_topic,
        labels = %if s.labels_topic.is_empty() { "(vref's segmenter)" } else { &s.labels_topic },
        markers = %s.markers_topic,
        service = %s.latest_gesture_service,
        "vref-ros2 running"
    );

    let mut counts = Counts::default();
    // [ros2] keeps it under 90 degrees, so under the matcher's pi/2.
    let cone = s.pointing_cone_deg.to_radians() as f32;
    let frames = Frames {
        robot: &s.robot_frame_id,
        headset: &s.headset_frame_id,
    };
    let mut robot_view: Option<View> = None;
    let mut answer: Option<Asked> = None;
    let mut news = NewAnswers::default();
    let mut scene_changed = false;
    let marker_period = Duration::from_secs_f64(1.0 / s.marker_rate_hz);
    let answer_period = Duration::from_secs_f64(1.0 / s.answer_rate_hz);
    let query_timeout = Duration::from_millis(s.query_timeout_ms);
    let mut last_markers: Option<Instant> = None;
    let asker = Asker::start(ipc, answer_period, query_timeout)?;
    let mut last_summary = Instant::now();

    while nap(&node, TURN) {
        if let Some(view) = robot_camera.drain(&mut counts, max)? {
            robot_view = Some(view);
            scene_changed = true;
        }
        if let Some(camera) = &mut headset_camera {
            // The human view comes back through the snapshot service below.
            camera.drain(&mut counts, max)?;
        }
        if let Some((sub, publisher)) = &mut pointing {
            loop {
                match sub.take() {
                    Ok(Some((pose, _))) => match ray_of(&pose.pose) {
                        Some((origin, direction)) => {
                            publisher.publish(
                                origin,
                                direction,
                                cone,
                                s.pointing_confidence as f32,
                            )?;
                            counts.rays += 1;
                        }
                        None => counts.skip(
                            "pointing",
                            "pose",
                            &"a pose that is not finite or not a rotation",
                        ),
                    },
                    Ok(None) => break,
                    Err(e) => {
                        counts.skip("pointing", "cdr", &format!("{e:?}"));
                        break;
                    }
                }
            }
        }

        // The matcher's side: the human view and decisions.
        let taken = matcher.take();
        scene_changed |= taken.view || taken.decision;
        if taken.decision
            && let Some(pose) = matcher
                .decision
                .as_ref()
                .and_then(|d| headset_pose(d, &s.robot_frame_id, Time::from_ns(now_ns())))
        {
            match pose_pub.publish(pose) {
                Ok(()) => counts.headset_poses += 1,
                Err(e) => tracing::warn!("publishing the headset pose: {e:?}"),
            }
        }

        // Service requests go to the asking thread; answers come back.
        loop {
            match server.receive_request() {
                Ok(Some((id, _))) => {
                    counts.service_calls += 1;
                    if asker.requests.send(id).is_err() {
                        let reply = trigger_failure("vref-ros2's asking thread stopped");
                        if let Err(e) = server.send_response(id, reply) {
                            tracing::warn!("answering the service: {e:?}");
                        }
                    }
                }
                Ok(None) => break,
                Err(e) => {
                    tracing::warn!("reading a service request: {e:?}");
                    break;
                }
            }
        }
        while let Ok((who, result)) = asker.answers.try_recv() {
            match who {
                AskFor::Service(id) => {
                    let reply = match &result {
                        Ok(asked) => trigger_response(asked),
                        Err(e) => trigger_failure(e),
                    };
                    if let Err(e) = server.send_response(id, reply) {
                        tracing::warn!("answering the service: {e:?}");
                    }
                }
                AskFor::Topic => {}
            }
            let Ok(asked) = result else { continue };
            // A new ok answer goes out once, whoever asked.
            if news.is_new(&asked.answer)
                && let Some(p) =
                    referenced_point(&asked.answer, &s.robot_frame_id, Time::from_ns(now_ns()))
            {
                match point_pub.publish(p) {
                    Ok(()) => counts.referenced += 1,
                    Err(e) => tracing::warn!("publishing the referenced object: {e:?}"),
                }
            }
            if answer.is_none_or(|a| a.answer != asked.answer) {
                scene_changed = true;
            }
            answer = Some(asked);
        }

        if scene_changed && last_markers.is_none_or(|t| t.elapsed() >= marker_period) {
            let scene = Scene {
                robot: robot_view.as_ref(),
                human: matcher.human_view.as_ref(),
                decision: matcher.decision.as_ref(),
                answer: answer.as_ref().map(|a| &a.answer),
            };
            match markers_pub.publish(markers(&scene, frames, Time::from_ns(now_ns()))) {
                Ok(()) => counts.marker_arrays += 1,
                Err(e) => tracing::warn!("publishing markers: {e:?}"),
            }
            last_markers = Some(Instant::now());
            scene_changed = false;
        }
        if last_summary.elapsed() >= SUMMARY_EVERY {
            last_summary = Instant::now();
            counts.log("vref-ros2 counts");
        }
    }
    counts.log("vref-ros2 stopped");
    Ok(counts)
}

fn ask(client: &mut ReferenceClient, timeout: Duration) -> Result<Asked, IpcError> {
    let start = Instant::now();
    let answer = client.latest_gesture(timeout)?;
    Ok(Asked {
        answer,
        round_trip_us: start.elapsed().as_micros() as u64,
        received_ns: now_ns(),
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
    use super::*;
    use crate::msg::{Point, Pose, Quaternion};

    #[test]
    fn a_pointing_pose_points_along_its_x_axis() {
        let identity = Pose {
            position: Point::from([0.1, 0.2, 0.3]),
            orientation: Quaternion::default(),
        };
        let (o, d) = ray_of(&identity).unwrap();
        assert_eq!(o, [0.1, 0.2, 0.3]);
        assert_eq!(d, [1.0, 0.0, 0.0]);
        // A quarter turn about y takes x to -z; the quaternion need not be
        // of unit length.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let turned = Pose {
            orientation: Quaternion {
                x: 0.0,
                y: 2.0 * h,
                z: 0.0,
                w: 2.0 * h,
            },
            ..identity
        };
        let (_, d) = ray_of(&turned).unwrap();
        assert!((d[0]).abs() < 1e-6 && (d[2] + 1.0).abs() < 1e-6, "{d:?}");
        let zero = Pose {
            orientation: Quaternion {
                x: 0.0,
                y: 0.0,
                z: 0.0,
                w: 0.0,
            },
            ..identity
        };
        assert!(ray_of(&zero).is_none());
    }
}
