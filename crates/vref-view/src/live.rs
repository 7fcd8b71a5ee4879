//! The viewer as a process: subscribes to vref's services (latest wins,
//! so it never holds a publisher back), keeps the latest of each, and
//! logs scenes, transforms, messages and (when given) the cameras'
//! images to a Foxglove WebSocket server and/or an MCAP file. The matcher
//! sees one more subscriber per service and, if asked for, one
//! latest-gesture query now and then.

use std::fs::File;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use foxglove::messages::Timestamp;
use foxglove::{Context, McapCompression, McapWriteOptions};
use iceoryx2::prelude::*;
use vref_record::WireChannel;
use vref_scene::Side;
use vref_wire::bytes::{put_sample, to_bytes};
use vref_wire::ipc::{
    Decision, IpcSettings, ReferenceClient, create_node, drain, now_ns, open_decision,
    open_gesture, open_snapshot, open_stats, termination_requested,
};

use crate::channels::{Channels, is_wire};
use crate::frames::{FrameNames, Placement, transforms};
use crate::images::{Images, annotation_key, annotations, calibration, compressed_image};
use crate::scene::{marker_size, scene};
use crate::state::{Asked, Latest, View};
use crate::{ViewError, json};

/// Uncompressed bytes per MCAP chunk: what a recorder killed with -9
/// loses at most (a few seconds of snapshots; images fill a chunk sooner).
const MCAP_CHUNK_BYTES: u64 = 256 * 1024;
/// Longest wait for an answer to the viewer's own query.
const ANSWER_TIMEOUT: Duration = Duration::from_millis(250);
/// A scene is sent at least this often, so that a client that connects
/// while nothing moves still gets one.
const KEEPALIVE: Duration = Duration::from_secs(1);
/// Longest sleep between checks of the clock and the stop flag.
const TICK: Duration = Duration::from_millis(100);
/// A camera's image (about 55 KB for a BOP JPEG) is logged when its scene
/// changes and again this often, so that a client that connects late
/// sees one within this time; more often would only grow the files.
const IMAGE_KEEPALIVE: Duration = Duration::from_secs(2);

/// What to view, where, for how long.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewOptions {
    /// Serve the Foxglove WebSocket protocol on this address (port 0: a
    /// free one, see [`Started::port`]).
    pub listen: Option<SocketAddr>,
    /// Write every channel, the raw wire ones too, to this MCAP file
    /// (created or truncated).
    pub mcap: Option<PathBuf>,
    /// Stop after this long; without it only SIGINT/SIGTERM stop.
    pub duration: Option<Duration>,
    /// Most scene updates per second.
    pub scene_rate_hz: f64,
    /// Latest-gesture queries per second (0: none), whose answers are
    /// shown: the viewer cannot see other clients' answers.
    pub answer_rate_hz: f64,
    /// The cameras' images of every scene the feeds may show; each
    /// camera's image follows the scene its latest snapshot is of.
    pub images: Option<Arc<Images>>,
}

/// What is known once the outputs are open.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Started {
    /// The WebSocket server's port, if it listens.
    pub port: Option<u16>,
}

/// Messages logged, by channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Counts {
    /// In [`WireChannel::ALL`] order.
    pub wire: [u64; 4],
    pub scenes: u64,
    pub transforms: u64,
    pub answers: u64,
    pub stats: u64,
    pub decisions: u64,
    /// Images logged, both cameras; as many calibrations go with them.
    pub images: u64,
    pub annotations: u64,
}

impl Counts {
    pub fn wire(&self, channel: WireChannel) -> u64 {
        let [robot, human, gesture, decision] = self.wire;
        match channel {
            WireChannel::RobotSnapshot => robot,
            WireChannel::HumanSnapshot => human,
            WireChannel::Gesture => gesture,
            WireChannel::Decision => decision,
        }
    }

    fn count_wire(&mut self, channel: WireChannel) {
        let [robot, human, gesture, decision] = &mut self.wire;
        match channel {
            WireChannel::RobotSnapshot => *robot += 1,
            WireChannel::HumanSnapshot => *human += 1,
            WireChannel::Gesture => *gesture += 1,
            WireChannel::Decision => *decision += 1,
        }
    }

    /// Every message logged.
    pub fn total(&self) -> u64 {
        self.wire.iter().sum::<u64>()
            + self.scenes
            + self.transforms
            + self.answers
            + self.stats
            + self.decisions
            + 2 * self.images
            + self.annotations
    }
}

/// Opens the outputs, calls `on_started`, then views until the duration
/// is over or SIGINT/SIGTERM; closes the outputs (an MCAP file is complete
/// only then).
pub fn run(
    ipc: &IpcSettings,
    options: &ViewOptions,
    on_started: impl FnOnce(&Started),
) -> Result<Counts, ViewError> {
    let ctx = Context::new();
    let channels = Channels::new(&ctx, options.images.is_some())?;
    let mcap =
        match &options.mcap {
            Some(path) => {
                let file = File::create(path).map_err(|source| ViewError::Create {
                    path: path.clone(),
                    source,
                })?;
                // Each chunk is built in memory and written whole when it is
                // finished (no seeking back to patch a chunk's header), with
                // no buffer of our own in between: a recorder killed with -9
                // leaves every finished chunk readable (vref_record::read_recording).
                let write = McapWriteOptions::default()
                    .compression(Some(McapCompression::Zstd))
                    .disable_seeking(true)
                    .chunk_size(Some(MCAP_CHUNK_BYTES));
                Some(ctx.mcap_writer_with_options(write).create(file).map_err(
                    ViewError::foxglove(format!("MCAP writer {}", path.display())),
                )?)
            }
            None => None,
        };
    let server = match options.listen {
        Some(addr) => Some(
            ctx.websocket_server()
                .name("vref")
                .bind(addr.ip().to_string(), addr.port())
                .channel_filter_fn(|c| !is_wire(c))
                .start_blocking()
                .map_err(ViewError::foxglove(format!("WebSocket server on {addr}")))?,
        ),
        None => None,
    };
    on_started(&Started {
        port: server.as_ref().map(|s| s.port()),
    });
    let counts = watch(ipc, options, &channels);
    if let Some(server) = server {
        server.stop().wait_blocking();
    }
    if let Some(mcap) = mcap {
        mcap.close()
            .map_err(ViewError::foxglove("closing the MCAP file"))?;
    }
    counts
}

/// The latest-gesture queries, on a thread of their own so that a slow
/// or absent matcher never delays the subscriptions.
struct Asker {
    stop: Arc<AtomicBool>,
    answers: mpsc::Receiver<Asked>,
    thread: JoinHandle<()>,
}

impl Asker {
    fn start(ipc: &IpcSettings, rate_hz: f64) -> Option<Self> {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return None;
        }
        let period = Duration::from_secs_f64(1.0 / rate_hz.min(1000.0));
        let stop = Arc::new(AtomicBool::new(false));
        let (tx, answers) = mpsc::channel();
        let ipc = ipc.clone();
        let stopped = stop.clone();
        let thread = std::thread::spawn(move || {
            let name = format!("vref-view-ask-{}", std::process::id());
            let mut client = match ReferenceClient::connect(&ipc, &name) {
                Ok(client) => client,
                Err(e) => {
                    tracing::warn!("no answers will be shown: {e}");
                    return;
                }
            };
            while !stopped.load(Ordering::Relaxed) {
                let asked = Instant::now();
                match client.latest_gesture(ANSWER_TIMEOUT) {
                    Ok(answer) => {
                        let round_trip_us =
                            u64::try_from(asked.elapsed().as_micros()).unwrap_or(u64::MAX);
                        let reply = Asked {
                            answer,
                            round_trip_us,
                            received_ns: now_ns(),
                        };
                        if tx.send(reply).is_err() {
                            return;
                        }
                    }
                    Err(e) => tracing::debug!("latest-gesture query: {e}"),
                }
                while asked.elapsed() < period && !stopped.load(Ordering::Relaxed) {
                    std::thread::sleep((period - asked.elapsed().min(period)).min(TICK));
                }
            }
        });
        Some(Self {
            stop,
            answers,
            thread,
        })
    }

    fn finish(self) {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.join().ok();
    }
}

fn timestamp(ns: u64) -> Timestamp {
    let sec = u32::try_from(ns / 1_000_000_000).unwrap_or(u32::MAX);
    Timestamp::new(sec, (ns % 1_000_000_000) as u32)
}

/// Subscribes and logs until the duration is over or a termination
/// request.
fn watch(
    ipc: &IpcSettings,
    options: &ViewOptions,
    channels: &Channels,
) -> Result<Counts, ViewError> {
    let node = create_node(ipc, &format!("vref-view-{}", std::process::id()))?;
    let (robot_data, robot_event) = open_snapshot(&node, ipc, Side::Robot)?;
    let (human_data, human_event) = open_snapshot(&node, ipc, Side::Human)?;
    let (gesture_data, gesture_event) = open_gesture(&node, ipc)?;
    let (decision_data, decision_event) = open_decision(&node, ipc)?;
    let stats_data = open_stats(&node, ipc)?;
    let robot = robot_data
        .subscriber_builder()
        .create()
        .map_err(|e| ViewError::iceoryx("robot snapshot subscriber")(&e))?;
    let human = human_data
        .subscriber_builder()
        .create()
        .map_err(|e| ViewError::iceoryx("human snapshot subscriber")(&e))?;
    let gesture = gesture_data
        .subscriber_builder()
        .create()
        .map_err(|e| ViewError::iceoryx("gesture subscriber")(&e))?;
    let decision = decision_data
        .subscriber_builder()
        .create()
        .map_err(|e| ViewError::iceoryx("decision subscriber")(&e))?;
    let stats = stats_data
        .subscriber_builder()
        .create()
        .map_err(|e| ViewError::iceoryx("stats subscriber")(&e))?;
    let listeners = [robot_event, human_event, gesture_event, decision_event]
        .iter()
        .map(|event| {
            event
                .listener_builder()
                .create()
                .map_err(|e| ViewError::iceoryx("listener")(&e))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let waitset = WaitSetBuilder::new()
        .create::<ipc::Service>()
        .map_err(|e| ViewError::iceoryx("waitset")(&e))?;
    let _guards = listeners
        .iter()
        .map(|l| waitset.attach_notification(l))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| ViewError::iceoryx("attaching a listener")(&e))?;

    let asker = Asker::start(ipc, options.answer_rate_hz);
    let period = Duration::from_secs_f64(1.0 / options.scene_rate_hz.clamp(0.1, 1000.0));
    let started = Instant::now();
    let end = options.duration.map(|d| started + d);
    let mut latest = Latest::default();
    let mut counts = Counts::default();
    let mut bytes = Vec::new();
    let mut changed = false;
    let mut last_scene: Option<Instant> = None;
    let mut shown = [Shown::default(), Shown::default()];
    let failure = 'outer: loop {
        let now = Instant::now();
        if end.is_some_and(|end| now >= end) {
            break None;
        }
        let wait = end.map_or(TICK, |end| (end - now).min(TICK));
        match waitset.wait_and_process_once_with_timeout(|_| CallbackProgression::Continue, wait) {
            Ok(result) if termination_requested(&result) => break None,
            Ok(_) => {}
            Err(e) => break Some(ViewError::iceoryx("waiting")(&e)),
        }
        for l in &listeners {
            l.try_wait(|_| {}).ok();
        }
        for (side, sub, channel) in [
            (Side::Robot, &robot, WireChannel::RobotSnapshot),
            (Side::Human, &human, WireChannel::HumanSnapshot),
        ] {
            let taken = drain::each(sub, |sample| {
                let wire = channels.wire(channel);
                if wire.has_sinks() {
                    bytes.clear();
                    put_sample(sample.user_header(), sample.payload(), &mut bytes);
                    wire.log(&bytes);
                    counts.count_wire(channel);
                }
                let view = View::from_wire(sample.user_header(), sample.payload());
                match side {
                    Side::Robot => latest.robot = Some(view),
                    Side::Human => latest.human = Some(view),
                }
                changed = true;
            });
            if let Err(e) = taken {
                break 'outer Some(ViewError::iceoryx("receiving a snapshot")(&e));
            }
        }
        let taken = drain::each(&gesture, |sample| {
            let ray = *sample.payload();
            let wire = channels.wire(WireChannel::Gesture);
            if wire.has_sinks() {
                wire.log(&to_bytes(&ray));
                counts.count_wire(WireChannel::Gesture);
            }
            latest.ray = Some(ray);
            changed = true;
        });
        if let Err(e) = taken {
            break 'outer Some(ViewError::iceoryx("receiving a ray")(&e));
        }
        let taken = drain::each(&decision, |sample| {
            let wire = channels.wire(WireChannel::Decision);
            if wire.has_sinks() {
                bytes.clear();
                put_sample(sample.user_header(), sample.payload(), &mut bytes);
                wire.log(&bytes);
                counts.count_wire(WireChannel::Decision);
            }
            match Decision::read(sample.user_header(), sample.payload()) {
                Ok(d) => {
                    if channels.decision.has_sinks() {
                        log_json(&channels.decision, &json::decision(&d));
                        counts.decisions += 1;
                    }
                    latest.decision = Some(d);
                    changed = true;
                }
                Err(e) => tracing::warn!("decision refused: {e}"),
            }
        });
        if let Err(e) = taken {
            break 'outer Some(ViewError::iceoryx("receiving a decision")(&e));
        }
        let taken = drain::each(&stats, |sample| {
            let s = *sample.payload();
            if channels.stats.has_sinks() {
                log_json(&channels.stats, &json::stats(&s));
                counts.stats += 1;
            }
            latest.stats = Some(s);
        });
        if let Err(e) = taken {
            break 'outer Some(ViewError::iceoryx("receiving statistics")(&e));
        }
        if let Some(asker) = &asker {
            while let Ok(asked) = asker.answers.try_recv() {
                if channels.answer.has_sinks() {
                    log_json(&channels.answer, &json::answer(&asked));
                    counts.answers += 1;
                }
                latest.answer = Some(asked);
                changed = true;
            }
        }
        let due = last_scene.is_none_or(|t| {
            let since = t.elapsed();
            (changed && since >= period) || since >= KEEPALIVE
        });
        if due {
            let names = FrameNames::of(&latest);
            let time = timestamp(now_ns());
            if channels.scene.has_sinks() || channels.tf.has_sinks() {
                let placement = Placement::of(&latest, 3.0 * marker_size(&latest));
                if channels.tf.has_sinks() {
                    channels.tf.log(&transforms(&names, &placement, time));
                    counts.transforms += 1;
                }
                if channels.scene.has_sinks() {
                    channels
                        .scene
                        .log(&scene(&latest, &names, &placement, time));
                    counts.scenes += 1;
                }
            }
            if let Some(images) = &options.images {
                let [robot, human] = &mut shown;
                for (side, shown) in [(Side::Robot, robot), (Side::Human, human)] {
                    show_camera(
                        images,
                        side,
                        &latest,
                        &names,
                        channels,
                        shown,
                        time,
                        &mut counts,
                    );
                }
            }
            last_scene = Some(Instant::now());
            changed = false;
        }
    };
    if let Some(asker) = asker {
        asker.finish();
    }
    match failure {
        Some(e) => Err(e),
        None => Ok(counts),
    }
}

/// What one camera's channels last showed.
#[derive(Debug, Default)]
struct Shown {
    scene: Option<usize>,
    image_at: Option<Instant>,
    annotations: Vec<String>,
    annotations_at: Option<Instant>,
}

/// Logs the image of the scene `side`'s latest snapshot is of, when that
/// scene changed or the last image is [`IMAGE_KEEPALIVE`] old, and its
/// outlines when what they show changed or is [`KEEPALIVE`] old.
#[allow(clippy::too_many_arguments)]
fn show_camera(
    images: &Images,
    side: Side,
    latest: &Latest,
    names: &FrameNames,
    channels: &Channels,
    shown: &mut Shown,
    time: Timestamp,
    counts: &mut Counts,
) {
    let (view, frame) = match side {
        Side::Robot => (&latest.robot, &names.robot),
        Side::Human => (&latest.human, &names.human),
    };
    let Some(channels) = channels.camera(side).filter(|c| c.has_sinks()) else {
        return;
    };
    let Some((index, scene)) = view
        .as_ref()
        .and_then(|v| images.scene_of(side, v))
        .and_then(|k| Some((k, images.scenes().get(k)?)))
    else {
        return;
    };
    let camera = scene.camera(side);
    let new_scene = shown.scene != Some(index);
    let old = |at: Option<Instant>, limit: Duration| at.is_none_or(|t| t.elapsed() >= limit);
    if new_scene || old(shown.image_at, IMAGE_KEEPALIVE) {
        channels.image.log(&compressed_image(camera, frame, time));
        channels.calibration.log(&calibration(camera, frame, time));
        counts.images += 1;
        shown.scene = Some(index);
        shown.image_at = Some(Instant::now());
    }
    let key = annotation_key(camera, side, latest);
    if new_scene || key != shown.annotations || old(shown.annotations_at, KEEPALIVE) {
        channels
            .annotations
            .log(&annotations(camera, side, latest, &scene.name, time));
        counts.annotations += 1;
        shown.annotations = key;
        shown.annotations_at = Some(Instant::now());
    }
}

fn log_json(channel: &foxglove::RawChannel, value: &serde_json::Value) {
    match serde_json::to_vec(value) {
        Ok(bytes) => channel.log(&bytes),
        Err(e) => tracing::warn!("encoding {}: {e}", channel.topic()),
    }
}
