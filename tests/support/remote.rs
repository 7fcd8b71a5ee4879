//! A robot with its bridge on a loopback port, and a headset simulator on
//! the other side of Zenoh, for the remote tests. Every endpoint is on
//! 127.0.0.1; no session scouts or listens anywhere else.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use vref_bridge::json::{ObjectJson, SnapshotIn};
use vref_bridge::{BridgeStats, Format, Keys, Message, RemoteClient, binary, json};
use vref_inject::{VALID_FEATURE_DIM, valid_objects};
use vref_scene::Side;
use vref_wire::ipc::IpcSettings;
use vref_wire::{
    FRAME_NAME_LEN, ObjectEntry, PointingRay, ReferenceAnswer, ReferenceQuery, SCHEMA_VERSION,
    SideCode, SnapshotHeader,
};
use zenoh::Wait;

use vref_testkit::{Harness, eventually};

use super::table;

/// One robot: its harness (own iceoryx2 root and prefix), the dataset its
/// feeds publish, its bridge's endpoint and key prefix.
#[derive(Debug)]
pub struct Robot {
    pub h: Harness,
    pub ipc: IpcSettings,
    pub source: String,
    pub endpoint: String,
    pub prefix: String,
}

impl Robot {
    /// `bridge` is appended to the `[bridge]` table (listen and prefix
    /// are set here); `robot_offset` shifts the robot's track ids, so
    /// that two robots give different answers.
    pub fn new(tag: &str, bridge: &str, robot_offset: u64) -> Self {
        let endpoint = format!("tcp/127.0.0.1:{}", vref_testkit::free_port());
        let prefix = format!("vref/t{}{tag}", std::process::id());
        let extra = format!(
            "[matching]\nbeta = 0.01\n\n[bridge]\nlisten = [\"{endpoint}\"]\nprefix = \"{prefix}\"\n\
             state_rate_hz = 20.0\n{bridge}"
        );
        let h = Harness::new(tag, &extra);
        let scene = h.dir.path().join("table.jsonl");
        std::fs::write(&scene, shifted(&table::dataset(), robot_offset)).unwrap();
        let config = vref_config::Config::from_file(&h.config).unwrap();
        Self {
            h,
            ipc: config.ipc,
            source: format!("dataset:{}", scene.display()),
            endpoint,
            prefix,
        }
    }

    /// The matcher and the robot's camera; the human view comes from the
    /// network.
    pub fn start_robot_side(&mut self) {
        self.h.start("matcher", "vref-matcher", &[]);
        let source = self.source.clone();
        self.h.start(
            "perception",
            "vref-perception-feed",
            &["--source", &source, "--rate", "50"],
        );
    }

    /// The local gesture feed instead of a headset (fleet test).
    pub fn start_local_headset(&mut self) {
        let source = self.source.clone();
        self.h.start(
            "gesture",
            "vref-gesture-feed",
            &["--source", &source, "--rate", "50"],
        );
    }

    pub fn start_bridge(&mut self) {
        self.h.start("bridge", "vref-bridge", &[]);
    }

    pub fn keys(&self) -> Keys {
        Keys::new(&self.prefix).unwrap()
    }

    /// A remote client, once the bridge accepts connections.
    pub fn remote(&self, format: Format) -> RemoteClient {
        eventually(Duration::from_secs(20), "the bridge listening", || {
            RemoteClient::connect(&self.endpoint, &self.prefix, format).ok()
        })
    }

    /// A client session to the bridge, once it accepts connections.
    pub fn session(&self) -> zenoh::Session {
        vref_testkit::bridge_session(
            std::slice::from_ref(&self.endpoint),
            Duration::from_secs(20),
        )
    }
}

/// The table dataset with the robot's track ids (and the truth) shifted
/// by `offset`.
fn shifted(dataset: &str, offset: u64) -> String {
    let mut line: serde_json::Value = serde_json::from_str(dataset.trim()).unwrap();
    for object in line["robot"]["objects"].as_array_mut().unwrap() {
        let id = object["id"].as_u64().unwrap();
        object["id"] = (id + offset).into();
    }
    for pair in line["ground_truth"].as_array_mut().unwrap() {
        let id = pair[1].as_u64().unwrap();
        pair[1] = (id + offset).into();
    }
    format!("{line}\n")
}

pub fn human_object(id: u64) -> ReferenceQuery {
    ReferenceQuery::human_object(id)
}

pub fn ray_query(origin: [f32; 3], direction: [f32; 3], cone: f32) -> ReferenceQuery {
    ReferenceQuery::ray(origin, direction, cone)
}

pub fn latest_gesture() -> ReferenceQuery {
    ReferenceQuery::latest_gesture()
}

/// Asks until the answer satisfies `good`, at most `limit`.
pub fn answer_until(
    client: &mut RemoteClient,
    query: ReferenceQuery,
    limit: Duration,
    what: &str,
    good: impl Fn(&ReferenceAnswer) -> bool,
) -> ReferenceAnswer {
    eventually(limit, what, || {
        let a = client.ask(query, Duration::from_millis(500)).ok()?;
        good(&a).then_some(a)
    })
}

/// The headset's view of the table, as the headset app sends it.
pub fn human_view_json(session: u64, sequence: u64) -> Vec<u8> {
    let objects = valid_objects(Side::Human)
        .iter()
        .map(|o| ObjectJson {
            track_id: o.track_id,
            position: o.position,
            position_sigma: o.position_sigma,
            feature: o.feature[..VALID_FEATURE_DIM].to_vec(),
        })
        .collect();
    json::encode_snapshot_in(&SnapshotIn {
        session,
        sequence,
        frame_name: Some("test_headset".to_owned()),
        up: None,
        objects,
    })
}

/// The same in the binary layout; `edit` may spoil the objects.
pub fn human_view_binary(
    session: u64,
    sequence: u64,
    edit: impl Fn(&mut Vec<ObjectEntry>),
) -> Vec<u8> {
    let mut entries = valid_objects(Side::Human);
    edit(&mut entries);
    let mut frame_name = [0; FRAME_NAME_LEN];
    frame_name[..12].copy_from_slice(b"test_headset");
    let header = SnapshotHeader {
        session,
        sequence,
        timestamp_ns: 0,
        schema_version: SCHEMA_VERSION,
        side: SideCode::Human as u32,
        object_count: entries.len() as u32,
        feature_dim: VALID_FEATURE_DIM as u32,
        frame_name,
        up: [0.0; 3],
        flags: 0,
    };
    binary::encode_snapshot(&header, &entries)
}

/// A ray from the headset's origin at human object `h`.
pub fn ray_at(session: u64, sequence: u64, h: u64) -> PointingRay {
    let target = valid_objects(Side::Human)
        .into_iter()
        .find(|o| o.track_id == h)
        .unwrap();
    PointingRay {
        session,
        sequence,
        timestamp_ns: 0,
        origin: [0.0; 3],
        direction: target.position,
        cone_half_angle: 0.05,
        confidence: 0.9,
        schema_version: SCHEMA_VERSION,
        reserved: 0,
    }
}

/// A headset app on another computer: publishes the table's human view
/// at 30 Hz and, every sixth snapshot, a ray at `points_at`, until
/// stopped. A burst asked for with [`Headset::burst`] is sent between two
/// ticks, with the session's own sequence numbers (a headset gone wild).
#[derive(Debug)]
pub struct Headset {
    stop: Arc<AtomicBool>,
    burst: Arc<AtomicU64>,
    published: Arc<AtomicU64>,
    thread: Option<JoinHandle<()>>,
    pub session: u64,
}

impl Headset {
    pub fn start(robot: &Robot, format: Format, session: u64, points_at: u64) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let burst = Arc::new(AtomicU64::new(0));
        let published = Arc::new(AtomicU64::new(0));
        let zenoh = robot.session();
        let keys = robot.keys();
        let thread = {
            let (stop, burst, published) = (stop.clone(), burst.clone(), published.clone());
            std::thread::spawn(move || {
                let snapshots = zenoh
                    .declare_publisher(keys.human_snapshot())
                    .encoding(Message::Snapshot.encoding(format))
                    .congestion_control(zenoh::qos::CongestionControl::Block)
                    .wait()
                    .unwrap();
                let rays = zenoh
                    .declare_publisher(keys.human_gesture())
                    .encoding(Message::Ray.encoding(format))
                    .wait()
                    .unwrap();
                let mut sequence = 0;
                let next = |sequence: &mut u64| {
                    *sequence += 1;
                    match format {
                        Format::Json => human_view_json(session, *sequence),
                        Format::Binary => human_view_binary(session, *sequence, |_| {}),
                    }
                };
                let period = Duration::from_millis(33);
                let mut tick = Instant::now();
                while !stop.load(Ordering::Relaxed) {
                    snapshots.put(next(&mut sequence)).wait().unwrap();
                    published.fetch_add(1, Ordering::Relaxed);
                    if sequence % 6 == 1 {
                        let ray = ray_at(session, sequence, points_at);
                        let bytes = match format {
                            Format::Json => json::encode_ray(&ray),
                            Format::Binary => binary::encode_ray(&ray),
                        };
                        rays.put(bytes).wait().unwrap();
                    }
                    for _ in 0..burst.swap(0, Ordering::Relaxed) {
                        snapshots.put(next(&mut sequence)).wait().unwrap();
                        published.fetch_add(1, Ordering::Relaxed);
                    }
                    tick += period;
                    std::thread::sleep(tick.saturating_duration_since(Instant::now()));
                }
                zenoh.close().wait().ok();
            })
        };
        Self {
            stop,
            burst,
            published,
            thread: Some(thread),
            session,
        }
    }

    /// Sends `n` snapshots at once, as fast as Zenoh takes them.
    pub fn burst(&self, n: u64) {
        self.burst.store(n, Ordering::Relaxed);
    }

    pub fn published(&self) -> u64 {
        self.published.load(Ordering::Relaxed)
    }

    /// The app quits (its session closes).
    pub fn stop(mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            thread.join().unwrap();
        }
    }
}

impl Drop for Headset {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            thread.join().ok();
        }
    }
}

/// The bridge's latest published counters, read from its stats key.
#[derive(Debug)]
pub struct BridgeStatsReader {
    subscriber:
        zenoh::pubsub::Subscriber<zenoh::handlers::FifoChannelHandler<zenoh::sample::Sample>>,
    _session: zenoh::Session,
}

impl BridgeStatsReader {
    pub fn new(robot: &Robot) -> Self {
        let session = robot.session();
        let subscriber = session
            .declare_subscriber(robot.keys().bridge_stats())
            .wait()
            .unwrap();
        Self {
            subscriber,
            _session: session,
        }
    }

    /// The newest counters published since the last call.
    pub fn latest(&self) -> Option<BridgeStats> {
        let mut latest = None;
        while let Ok(Some(sample)) = self.subscriber.try_recv() {
            latest = Some(BridgeStats::from_json(&sample.payload().to_bytes()).unwrap());
        }
        latest
    }

    /// Waits for counters that satisfy `good`.
    pub fn until(
        &self,
        limit: Duration,
        what: &str,
        good: impl Fn(&BridgeStats) -> bool,
    ) -> BridgeStats {
        eventually(limit, what, || self.latest().filter(|s| good(s)))
    }
}
