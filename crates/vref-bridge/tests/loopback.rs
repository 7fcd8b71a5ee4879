//! The bridge's loop in this process, between real iceoryx2 services (on
//! a root path and prefix of this test's own) and a Zenoh client on
//! loopback (tcp/127.0.0.1, no scouting): a headset snapshot reaches the
//! local service, the robot's snapshot reaches the network, a remote
//! query is answered by a stand-in matcher, refusals are counted, and the
//! loop stops when asked. Every wait is bounded.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use vref_bridge::json::{ObjectJson, SnapshotIn};
use vref_bridge::{
    BridgeError, BridgeStats, ErrorReply, Format, Keys, Message, RemoteClient, json,
};
use vref_config::Config;
use vref_logging::exit::Fault;
use vref_scene::Side;
use vref_testkit::{bridge_session, eventually, free_port};
use vref_wire::ipc::{
    SnapshotPublisher, answer_waiting, create_node, open_answer_event, open_reference,
    open_snapshot,
};
use vref_wire::{
    AnswerStatus, FRAME_NAME_LEN, MAX_FEATURE_DIM, ObjectEntry, ReferenceAnswer, ReferenceQuery,
    SCHEMA_VERSION, SideCode, SnapshotHeader,
};
use zenoh::Wait;

/// Longest any one step may take on a loaded machine.
const LIMIT: Duration = Duration::from_secs(30);

/// A configuration of this test's own: iceoryx2 under `root`, the bridge
/// listening on a loopback port only.
fn config(root: &std::path::Path, tag: &str) -> Config {
    let mut config = Config::default();
    config.ipc.root_path = Some(root.to_owned());
    config.ipc.prefix = format!("vb{}{tag}_", std::process::id());
    let bridge = &mut config.bridge;
    bridge.listen = vec![format!("tcp/127.0.0.1:{}", free_port())];
    bridge.multicast_scouting = false;
    bridge.prefix = format!("vref/lb{}{tag}", std::process::id());
    bridge.state_rate_hz = 20.0;
    bridge.query_timeout_ms = 300;
    config
}

/// The bridge's loop on a thread of its own, stopped and joined on drop.
struct Bridge {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<Result<(), BridgeError>>>,
}

impl Bridge {
    fn start(config: &Config) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let thread = {
            let (config, stop) = (config.clone(), Arc::clone(&stop));
            std::thread::spawn(move || vref_bridge::run_until(&config, &stop))
        };
        Self {
            stop,
            thread: Some(thread),
        }
    }

    /// Asks the loop to stop; what it ended with, within `LIMIT`.
    fn stop(mut self) -> Result<(), BridgeError> {
        self.stop.store(true, Ordering::Relaxed);
        let thread = self.thread.take().unwrap();
        eventually(LIMIT, "the bridge stopping", || {
            thread.is_finished().then_some(())
        });
        thread.join().unwrap()
    }
}

impl Drop for Bridge {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            let deadline = Instant::now() + LIMIT;
            while !thread.is_finished() && Instant::now() < deadline {
                std::thread::sleep(Duration::from_millis(20));
            }
            if thread.is_finished() {
                thread.join().ok();
            }
        }
    }
}

fn objects() -> Vec<ObjectJson> {
    (1..=4)
        .map(|id| ObjectJson {
            track_id: id,
            position: [0.1 * id as f32, 0.05 * id as f32, 1.0],
            position_sigma: [0.01; 3],
            feature: vec![1.0, id as f32, 0.5],
        })
        .collect()
}

fn entries() -> Vec<ObjectEntry> {
    objects()
        .into_iter()
        .map(|o| {
            let mut feature = [0.0; MAX_FEATURE_DIM];
            feature[..o.feature.len()].copy_from_slice(&o.feature);
            ObjectEntry {
                track_id: o.track_id + 100,
                position: o.position,
                position_sigma: o.position_sigma,
                feature,
            }
        })
        .collect()
}

fn robot_header(sequence: u64, count: usize) -> SnapshotHeader {
    let mut frame_name = [0; FRAME_NAME_LEN];
    frame_name[..5].copy_from_slice(b"robot");
    SnapshotHeader {
        session: 0x0B07,
        sequence,
        timestamp_ns: vref_wire::ipc::now_ns(),
        schema_version: SCHEMA_VERSION,
        side: SideCode::Robot as u32,
        object_count: count as u32,
        feature_dim: 3,
        frame_name,
        up: [0.0; 3],
        flags: 0,
    }
}

#[test]
fn headset_in_and_state_out_cross_between_zenoh_and_iceoryx2() {
    let root = tempfile::tempdir().unwrap();
    let config = config(root.path(), "x");
    let bridge = Bridge::start(&config);
    let zenoh = bridge_session(&config.bridge.listen, LIMIT);
    let keys = Keys::new(&config.bridge.prefix).unwrap();

    // Headset in: a JSON snapshot on the network is published locally as
    // the human view, under the bridge's own session.
    let node = create_node(&config.ipc, "loopback-test").unwrap();
    let (human, _) = open_snapshot(&node, &config.ipc, Side::Human).unwrap();
    let human: Subscriber<ipc::Service, [ObjectEntry], SnapshotHeader> =
        human.subscriber_builder().create().unwrap();
    let mut sequence = 0;
    let (header, received) = eventually(LIMIT, "a headset snapshot published locally", || {
        sequence += 1;
        let snapshot = json::encode_snapshot_in(&SnapshotIn {
            session: 0x4EAD,
            sequence,
            frame_name: Some("test_headset".to_owned()),
            up: None,
            objects: objects(),
        });
        zenoh
            .put(keys.human_snapshot(), snapshot)
            .encoding(Message::Snapshot.encoding(Format::Json))
            .wait()
            .unwrap();
        std::thread::sleep(Duration::from_millis(30));
        let sample = human.receive().unwrap()?;
        Some((*sample.user_header(), sample.payload().to_vec()))
    });
    assert_eq!(header.side, SideCode::Human as u32);
    assert_ne!(
        header.session, 0x4EAD,
        "published under the bridge's session"
    );
    let count = header.object_count as usize;
    let ids: Vec<u64> = received[..count].iter().map(|e| e.track_id).collect();
    assert_eq!(ids, [1, 2, 3, 4]);

    // State out: the robot's snapshot reaches a monitor on the network.
    let monitor = zenoh
        .declare_subscriber(keys.robot_snapshot())
        .wait()
        .unwrap();
    let mut robot = SnapshotPublisher::new(&node, &config.ipc, Side::Robot, "robot").unwrap();
    let mut sequence = 0;
    let view = eventually(LIMIT, "the robot's snapshot on the network", || {
        sequence += 1;
        let entries = entries();
        robot
            .publish_raw(robot_header(sequence, entries.len()), &entries)
            .unwrap();
        let sample = monitor.recv_timeout(Duration::from_millis(200)).ok()??;
        assert_eq!(sample.encoding().to_string(), "application/json");
        Some(json::decode_snapshot_out(&sample.payload().to_bytes()).unwrap())
    });
    let ids: Vec<u64> = view.objects.iter().map(|o| o.track_id).collect();
    assert_eq!(ids, [101, 102, 103, 104]);
    assert_eq!(view.frame_name, "robot");

    // The bridge's counters say what it did.
    let stats = zenoh
        .declare_subscriber(keys.bridge_stats())
        .wait()
        .unwrap();
    let counted: BridgeStats = eventually(LIMIT, "the bridge's statistics", || {
        let sample = stats.recv_timeout(Duration::from_millis(500)).ok()??;
        let s = BridgeStats::from_json(&sample.payload().to_bytes()).unwrap();
        (s.published.robot_snapshot > 0).then_some(s)
    });
    assert!(counted.published.human_snapshot >= 1);
    assert_eq!(counted.prefix, config.bridge.prefix);
    assert_eq!(counted.session, header.session);
    assert_eq!(counted.human_snapshot.refused_total(), 0);

    drop(monitor);
    drop(stats);
    zenoh.close().wait().unwrap();
    bridge.stop().unwrap();
}

/// A stand-in matcher: answers every query at once, naming robot object
/// `human_object_id + 100`, until `stop`.
fn stand_in_matcher(config: &Config, stop: Arc<AtomicBool>) -> JoinHandle<u64> {
    let ipc = config.ipc.clone();
    std::thread::spawn(move || {
        let node = create_node(&ipc, "loopback-matcher").unwrap();
        let server = open_reference(&node, &ipc)
            .unwrap()
            .server_builder()
            .create()
            .unwrap();
        let answers = open_answer_event(&node, &ipc)
            .unwrap()
            .notifier_builder()
            .create()
            .unwrap();
        let mut served = 0;
        let deadline = Instant::now() + LIMIT * 2;
        while !stop.load(Ordering::Relaxed) && Instant::now() < deadline {
            let done = answer_waiting(
                &server,
                |q: &ReferenceQuery, _| {
                    Some(ReferenceAnswer {
                        human_object_id: q.human_object_id,
                        robot_track_id: q.human_object_id + 100,
                        ..ReferenceAnswer::empty(q.request_id, AnswerStatus::Ok)
                    })
                },
                |_| {},
            );
            if done.sent > 0 {
                served += done.sent;
                answers.notify().unwrap();
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        served
    })
}

#[test]
fn remote_queries_are_answered_by_the_local_matcher_or_refused_with_a_reason() {
    let root = tempfile::tempdir().unwrap();
    let mut config = config(root.path(), "q");
    config.bridge.headset_in = false;
    config.bridge.state_out = false;
    let bridge = Bridge::start(&config);
    let zenoh = bridge_session(&config.bridge.listen, LIMIT);
    let keys = Keys::new(&config.bridge.prefix).unwrap();

    // No matcher yet: the query passes the intake and is refused as
    // unanswered, with the counter's name.
    let mut client =
        RemoteClient::new(zenoh.clone(), &config.bridge.prefix, Format::Binary).unwrap();
    let unanswered = eventually(LIMIT, "a reply from the bridge", || {
        match client.ask(ReferenceQuery::human_object(3), Duration::from_secs(5)) {
            Err(vref_bridge::NetError::Refused { message, .. }) => Some(message),
            _ => None,
        }
    });
    assert!(
        unanswered.contains("the matcher did not answer"),
        "{unanswered}"
    );

    // A malformed query is refused before it is asked.
    let replies = zenoh
        .get(keys.reference())
        .payload("{\"kind\": \"nothing\"}")
        .encoding(Message::Query.encoding(Format::Json))
        .timeout(Duration::from_secs(5))
        .wait()
        .unwrap();
    let reply = replies.recv_timeout(LIMIT).unwrap().unwrap();
    let Err(refusal) = reply.result() else {
        panic!("a malformed query must get an error reply");
    };
    let refusal: ErrorReply = serde_json::from_slice(&refusal.payload().to_bytes()).unwrap();
    assert_eq!(refusal.reason, "malformed");

    // With a matcher, the answer comes back in the query's encoding, with
    // the remote request id.
    let stop = Arc::new(AtomicBool::new(false));
    let matcher = stand_in_matcher(&config, Arc::clone(&stop));
    for format in [Format::Binary, Format::Json] {
        let mut client = RemoteClient::new(zenoh.clone(), &config.bridge.prefix, format).unwrap();
        let answer = eventually(LIMIT, "an answer from the stand-in matcher", || {
            client
                .ask(ReferenceQuery::human_object(3), Duration::from_secs(5))
                .ok()
        });
        assert_eq!(
            (answer.status(), answer.robot_track_id),
            (AnswerStatus::Ok, 103),
            "{format:?}"
        );
    }
    stop.store(true, Ordering::Relaxed);
    assert!(matcher.join().unwrap() >= 2);

    zenoh.close().wait().unwrap();
    bridge.stop().unwrap();
}

#[test]
fn a_bad_zenoh_endpoint_is_a_configuration_error() {
    let root = tempfile::tempdir().unwrap();
    let mut config = config(root.path(), "c");
    // Not checked here (run takes the configuration as given): Zenoh's
    // own check refuses it.
    config.bridge.listen = vec!["nonsense".to_owned()];
    let e = Bridge::start(&config).stop().unwrap_err();
    assert!(e.is_bad_input(), "{e:?}");
}
