//! `vref view` and MCAP recordings with real processes over real
//! iceoryx2: a Foxglove WebSocket client on loopback receives scene
//! updates; an MCAP recording reads back with the `mcap` crate (channels,
//! schemas, counts, the raw messages bit for bit), in Python's `mcap`
//! package too where it is installed, and replays to the same answers.
//! The decisions drawn are the matcher's own, published after each solve;
//! the dataset feeds publish no rays, so the tests point themselves. With
//! `--images`, the BOP scenes' images, calibrations and mask outlines
//! read back too.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use foxglove::Decode;
use foxglove::messages::{FrameTransforms, SceneUpdate};
use nix::sys::signal::Signal;
use support::table::table_harness;
use vref_inject::{VALID_FEATURE_DIM, robot_id, valid_objects};
use vref_scene::Side;
use vref_testkit::{Harness, binary, eventually, exit_within};
use vref_wire::bytes::take_sample;
use vref_wire::ipc::{GesturePublisher, IpcSettings, ReferenceClient, create_node};
use vref_wire::{AnswerStatus, ObjectEntry, ReferenceAnswer, SnapshotHeader};

const TOPICS: [&str; 9] = [
    "/vref/scene",
    "/tf",
    "/vref/answer",
    "/vref/matcher/stats",
    "/vref/matcher/decision",
    "/vref/wire/robot/snapshot",
    "/vref/wire/human/snapshot",
    "/vref/wire/human/gesture",
    "/vref/wire/matcher/decision",
];

fn start_system(h: &mut Harness, source: &str) {
    h.start("matcher", "vref-matcher", &[]);
    start_feeds(h, source);
}

fn start_feeds(h: &mut Harness, source: &str) {
    for (name, bin) in [
        ("perception", "vref-perception-feed"),
        ("gesture", "vref-gesture-feed"),
    ] {
        h.start(name, bin, &["--source", source, "--rate", "50"]);
    }
}

fn stop_feeds(h: &mut Harness) {
    for name in ["perception", "gesture"] {
        h.signal(name, Signal::SIGTERM);
        assert_eq!(h.wait(name, Duration::from_secs(10)).code(), Some(0));
    }
}

/// Every human object's answer, once all are `ok`.
fn answers(client: &mut ReferenceClient) -> Vec<ReferenceAnswer> {
    eventually(Duration::from_secs(20), "ok answers for the table", || {
        valid_objects(Side::Human)
            .iter()
            .map(|o| {
                let a = client
                    .by_human_object(o.track_id, Duration::from_millis(300))
                    .ok()?;
                (a.status() == AnswerStatus::Ok).then_some(a)
            })
            .collect()
    })
}

/// Publishes a ray pointing at human object 2 (the dataset feeds publish
/// none) every 100 ms until stopped.
struct Pointer {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<u64>>,
}

impl Pointer {
    fn start(ipc: &IpcSettings) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = stop.clone();
        let ipc = ipc.clone();
        let thread = std::thread::spawn(move || {
            let node = create_node(&ipc, "test-pointer").unwrap();
            let mut rays = GesturePublisher::new(&node, &ipc).unwrap();
            let humans = valid_objects(Side::Human);
            let mut published = 0;
            while !stopped.load(Ordering::Relaxed) {
                published += 1;
                rays.publish([0.0; 3], humans[1].position, 0.05, 0.9)
                    .unwrap();
                std::thread::sleep(Duration::from_millis(100));
            }
            published
        });
        Self {
            stop,
            thread: Some(thread),
        }
    }

    fn stop(&mut self) -> u64 {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.take().map_or(0, |t| t.join().unwrap())
    }
}

impl Drop for Pointer {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Per topic: message encoding, schema name and encoding, message count,
/// from the file's summary section.
fn summary(bytes: &[u8]) -> BTreeMap<String, (String, String, String, u64)> {
    let summary = mcap::Summary::read(bytes)
        .unwrap()
        .expect("a summary section");
    let stats = summary.stats.expect("statistics");
    summary
        .channels
        .values()
        .map(|c| {
            let (name, encoding) = c
                .schema
                .as_ref()
                .map(|s| (s.name.clone(), s.encoding.clone()))
                .unwrap_or_default();
            let count = stats
                .channel_message_counts
                .get(&c.id)
                .copied()
                .unwrap_or(0);
            (
                c.topic.clone(),
                (c.message_encoding.clone(), name, encoding, count),
            )
        })
        .collect()
}

/// The count after `label` in `vref record`'s summary line.
fn printed(stdout: &str, label: &str) -> u64 {
    stdout
        .split(&format!("{label} "))
        .nth(1)
        .and_then(|rest| rest.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no `{label}` in {stdout}"))
}

#[test]
fn an_mcap_recording_reads_back_with_the_mcap_crate_and_replays_to_the_same_answers() {
    let (mut h, ipc, source) = table_harness("mcap");
    start_system(&mut h, &source);
    let mut pointer = Pointer::start(&ipc);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    let live = answers(&mut client);

    let out = h.dir.path().join("table.mcap");
    let run = support::vref(
        &[
            "record",
            "--out",
            out.to_str().unwrap(),
            "--duration",
            "3s",
            "--answer-rate",
            "5",
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(60),
    )
    .ok();
    pointer.stop();
    let bytes = std::fs::read(&out).unwrap();

    // Channels and schemas, as a reader that vref did not write sees them.
    let channels = summary(&bytes);
    let topics: Vec<&str> = channels.keys().map(String::as_str).collect();
    let mut expected = TOPICS.to_vec();
    expected.sort_unstable();
    assert_eq!(topics, expected, "{channels:?}");
    let schema = |topic: &str| {
        let (encoding, name, schema_encoding, _) = &channels[topic];
        (encoding.as_str(), name.as_str(), schema_encoding.as_str())
    };
    assert_eq!(
        schema("/vref/scene"),
        ("protobuf", "foxglove.SceneUpdate", "protobuf")
    );
    assert_eq!(
        schema("/tf"),
        ("protobuf", "foxglove.FrameTransforms", "protobuf")
    );
    assert_eq!(
        schema("/vref/answer"),
        ("json", "vref.Answer", "jsonschema")
    );
    assert_eq!(
        schema("/vref/wire/robot/snapshot"),
        (
            "vref-wire",
            "vref::SnapshotHeader+[vref::ObjectEntry]",
            "vref-wire-layout"
        )
    );
    // Message counts: what vref said it wrote is what the file holds.
    let count = |topic: &str| channels[topic].3;
    for (topic, label) in [
        ("/vref/wire/robot/snapshot", "robot snapshots"),
        ("/vref/wire/human/snapshot", "human snapshots"),
        ("/vref/wire/human/gesture", "rays"),
        ("/vref/wire/matcher/decision", "decisions"),
        ("/vref/scene", "scene updates"),
        ("/tf", "transforms"),
        ("/vref/answer", "answers"),
    ] {
        assert_eq!(count(topic), printed(&run.stdout, label), "{topic}");
    }
    // 3 s of feeds at 50 Hz, decisions at 10 Hz, scenes at up to 10 Hz.
    assert!(count("/vref/wire/robot/snapshot") >= 10, "{channels:?}");
    assert!(count("/vref/wire/human/snapshot") >= 10, "{channels:?}");
    assert!(count("/vref/wire/matcher/decision") >= 3, "{channels:?}");
    assert!(count("/vref/scene") >= 3, "{channels:?}");
    assert!(count("/vref/wire/human/gesture") >= 3, "{channels:?}");
    assert!(count("/vref/answer") >= 1, "{channels:?}");

    // The raw messages are the table as published, bit for bit, and the
    // scenes draw it with the decision's colours.
    let robot = valid_objects(Side::Robot);
    let mut last_scene = None;
    let mut last_decision = None;
    let mut answered = Vec::new();
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let message = message.unwrap();
        match message.channel.topic.as_str() {
            "/vref/wire/robot/snapshot" => {
                let (header, entries): (SnapshotHeader, Vec<ObjectEntry>) =
                    take_sample("snapshot", &message.data).unwrap();
                assert_eq!(header.object_count as usize, robot.len());
                for (got, want) in entries.iter().zip(&robot) {
                    assert_eq!(got.track_id, want.track_id);
                    assert_eq!(
                        got.position.map(f32::to_bits),
                        want.position.map(f32::to_bits)
                    );
                    assert_eq!(
                        got.feature[..VALID_FEATURE_DIM],
                        want.feature[..VALID_FEATURE_DIM]
                    );
                }
            }
            "/vref/scene" => last_scene = Some(SceneUpdate::decode(&message.data[..]).unwrap()),
            "/vref/matcher/decision" => {
                last_decision =
                    Some(serde_json::from_slice::<serde_json::Value>(&message.data).unwrap());
            }
            "/vref/answer" => {
                let a: serde_json::Value = serde_json::from_slice(&message.data).unwrap();
                answered.push((a["status"].clone(), a["robot_track_id"].clone()));
            }
            "/tf" => {
                let tf = FrameTransforms::decode(&message.data[..]).unwrap();
                assert_eq!(tf.transforms.len(), 2);
            }
            _ => {}
        }
    }
    // The viewer's own latest-gesture queries: the ray points at human 2.
    let want = (serde_json::json!("ok"), serde_json::json!(robot_id(2)));
    assert!(answered.contains(&want), "{answered:?}");
    // The matcher's own decision: every human object matched to its
    // partner, with the motion estimated.
    let decision = last_decision.expect("the matcher's decisions");
    assert_eq!(decision["motion_estimated"], true, "{decision}");
    let pairs = decision["pairs"].as_array().unwrap();
    assert_eq!(pairs.len(), 6, "{decision}");
    for p in pairs {
        let human = p["human_track_id"].as_u64().unwrap();
        assert_eq!(p["status"], "ok", "{decision}");
        assert_eq!(
            p["robot_track_id"].as_u64(),
            Some(robot_id(human)),
            "{decision}"
        );
    }
    let scene = last_scene.unwrap();
    let entity = |id: &str| scene.entities.iter().find(|e| e.id == id).unwrap();
    assert_eq!(entity("robot/objects").spheres.len(), 6);
    assert_eq!(entity("human/objects").cubes.len(), 6);
    assert_eq!(entity("ray").arrows.len(), 1);
    let pairs = &entity("pairs").lines;
    assert_eq!(pairs.len(), 6);
    // Placed by the matcher's estimated motion, each human object lands on
    // its partner (within a centimetre: the estimate is a fit).
    for line in pairs {
        let (a, b) = (line.points[0], line.points[1]);
        let gap = ((a.x - b.x).powi(2) + (a.y - b.y).powi(2) + (a.z - b.z).powi(2)).sqrt();
        assert!(gap < 0.01, "pair line of {gap} m");
    }

    python_reads(&out, &TOPICS, "foxglove.SceneUpdate");

    // Replay: the feeds publish the recording, and the matcher answers as
    // it did live.
    stop_feeds(&mut h);
    eventually(Duration::from_secs(5), "stale without feeds", || {
        let a = client.by_human_object(1, Duration::from_millis(300)).ok()?;
        (a.status() == AnswerStatus::Stale).then_some(())
    });
    start_feeds(&mut h, &format!("recording:{}", out.display()));
    let replayed = answers(&mut client);
    for (live, replayed) in live.iter().zip(&replayed) {
        assert_eq!(
            (
                live.human_object_id,
                live.robot_track_id,
                live.position.map(f32::to_bits)
            ),
            (
                replayed.human_object_id,
                replayed.robot_track_id,
                replayed.position.map(f32::to_bits)
            )
        );
        assert_eq!(live.robot_track_id, robot_id(live.human_object_id));
    }
}

/// A child killed with SIGKILL when dropped, so that a failed test leaves
/// no recorder running.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        self.0.kill().ok();
        self.0.wait().ok();
    }
}

/// Issue 40, case 3: `vref record` killed with -9 leaves `F.mcap.tmp`,
/// which replay used to refuse whole ("Chunk ended in the middle of a
/// record"). Now every chunk finished before the kill is in the file, and
/// replay publishes them, saying where the file stops.
#[test]
fn a_recording_killed_with_sigkill_replays_its_finished_chunks() {
    let (mut h, ipc, source) = table_harness("kill9");
    start_system(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    answers(&mut client);
    let out = h.dir.path().join("table.mcap");
    let partial = h.dir.path().join("table.mcap.tmp");
    let mut recorder = Killed(
        Command::new(binary("vref"))
            .args([
                "record",
                "--out",
                out.to_str().unwrap(),
                "--duration",
                "120s",
            ])
            .args(["--config", h.config_arg()])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    eventually(
        Duration::from_secs(30),
        "finished chunks in the file",
        || {
            let bytes = std::fs::read(&partial).ok()?;
            let read = vref_record::read_recording(&bytes).ok()?;
            (read.frames.len() >= 100).then_some(())
        },
    );
    recorder.0.kill().unwrap();
    recorder.0.wait().unwrap();
    assert!(!out.exists());
    let bytes = std::fs::read(&partial).unwrap();
    // What replay used to read it with still refuses it.
    assert!(vref_record::read_frames(&bytes).is_err());

    stop_feeds(&mut h);
    eventually(Duration::from_secs(5), "stale without feeds", || {
        let a = client.by_human_object(1, Duration::from_millis(300)).ok()?;
        (a.status() == AnswerStatus::Stale).then_some(())
    });
    start_feeds(&mut h, &format!("recording:{}", partial.display()));
    let replayed = answers(&mut client);
    for a in &replayed {
        assert_eq!(a.robot_track_id, robot_id(a.human_object_id));
    }
    let log = h.log("perception");
    assert!(log.contains("the file is cut short"), "{log}");
}

/// Python's `mcap` package (a reader vref did not write), if installed:
/// the `topics` and schema names, and as many messages as the Rust reader
/// counts. `VREF_PYTHON` names the interpreter (tools/test.sh gives its
/// virtual environment's, which has the package: there a missing package
/// fails the test); without it, `python3`, and the check is skipped,
/// saying so, where that has no `mcap`.
fn python_reads(path: &std::path::Path, topics: &[&str], schema: &str) {
    let script = vref_testkit::repo_root().join("tools/check-mcap.py");
    let named = std::env::var("VREF_PYTHON").ok();
    let python = named.clone().unwrap_or_else(|| "python3".to_owned());
    let probe = Command::new(&python)
        .args(["-c", "import mcap"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    if !probe.is_ok_and(|s| s.success()) {
        assert!(
            named.is_none(),
            "VREF_PYTHON={python} cannot import mcap (tools/test.sh installs it in its venv)"
        );
        eprintln!("{python} with the mcap package not found: Python check skipped");
        return;
    }
    let out = Command::new(&python)
        .arg(&script)
        .arg(path)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}\n{stdout}",
        String::from_utf8_lossy(&out.stderr)
    );
    for topic in topics {
        assert!(stdout.contains(topic), "{topic} not in {stdout}");
    }
    assert!(stdout.contains(schema), "{stdout}");
}

/// A child process killed if the test ends early.
struct Reaped(Child);

impl Drop for Reaped {
    fn drop(&mut self) {
        if let Ok(None) = self.0.try_wait() {
            self.0.kill().ok();
            self.0.wait().ok();
        }
    }
}

/// Runs `vref view` and returns it with the port it serves.
fn start_view(h: &Harness) -> (Reaped, u16) {
    let mut child = Command::new(binary("vref"))
        .args([
            "view",
            "--listen",
            "127.0.0.1:0",
            "--duration",
            "60s",
            "--config",
            h.config_arg(),
        ])
        .env("RUST_LOG", "info")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let stdout = child.stdout.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut line = String::new();
        BufReader::new(stdout).read_line(&mut line).ok();
        tx.send(line).ok();
    });
    let line = rx
        .recv_timeout(Duration::from_secs(30))
        .expect("vref view names its address");
    let port = line
        .split("ws://127.0.0.1:")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|p| p.parse().ok())
        .unwrap_or_else(|| panic!("no port in {line:?}"));
    (Reaped(child), port)
}

#[test]
fn a_foxglove_websocket_client_receives_scene_updates_from_vref_view() {
    let (mut h, ipc, source) = table_harness("view");
    start_system(&mut h, &source);
    let _pointer = Pointer::start(&ipc);
    let (mut view, port) = start_view(&h);

    let stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_millis(500)))
        .unwrap();
    let mut request = tungstenite::client::IntoClientRequest::into_client_request(format!(
        "ws://127.0.0.1:{port}"
    ))
    .unwrap();
    request
        .headers_mut()
        .insert("Sec-WebSocket-Protocol", "foxglove.sdk.v1".parse().unwrap());
    let (mut socket, _) = tungstenite::client::client(request, stream).unwrap();

    let deadline = Instant::now() + Duration::from_secs(30);
    let mut subscribed = false;
    let mut scene: Option<SceneUpdate> = None;
    while Instant::now() < deadline {
        let message = match socket.read() {
            Ok(m) => m,
            Err(tungstenite::Error::Io(e))
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                continue;
            }
            Err(e) => panic!("reading from vref view: {e}"),
        };
        match message {
            tungstenite::Message::Text(text) => {
                let value: serde_json::Value = serde_json::from_str(&text).unwrap();
                if value["op"] != "advertise" {
                    continue;
                }
                for channel in value["channels"].as_array().unwrap() {
                    let topic = channel["topic"].as_str().unwrap();
                    assert!(!topic.starts_with("/vref/wire/"), "{topic} advertised");
                    if topic == "/vref/scene" && !subscribed {
                        assert_eq!(channel["schemaName"], "foxglove.SceneUpdate");
                        assert_eq!(channel["encoding"], "protobuf");
                        let subscribe = serde_json::json!({
                            "op": "subscribe",
                            "subscriptions": [{"id": 1, "channelId": channel["id"]}],
                        });
                        socket
                            .send(tungstenite::Message::text(subscribe.to_string()))
                            .unwrap();
                        subscribed = true;
                    }
                }
            }
            tungstenite::Message::Binary(data) => {
                // Message data: opcode 1, subscription id, log time, payload.
                assert_eq!(data[0], 1, "binary opcode");
                assert_eq!(u32::from_le_bytes(data[1..5].try_into().unwrap()), 1);
                let update = SceneUpdate::decode(&data[13..]).unwrap();
                let pairs = update
                    .entities
                    .iter()
                    .find(|e| e.id == "pairs")
                    .map_or(0, |e| e.lines.len());
                let done = pairs == 6;
                scene = Some(update);
                if done {
                    break;
                }
            }
            _ => {}
        }
    }
    assert!(subscribed, "the scene channel was never advertised");
    let scene = scene.expect("no scene update within 30 s");
    let entity = |id: &str| scene.entities.iter().find(|e| e.id == id).unwrap();
    assert_eq!(entity("robot/objects").spheres.len(), 6);
    assert_eq!(entity("human/objects").cubes.len(), 6);
    assert_eq!(entity("pairs").lines.len(), 6, "{scene:?}");
    socket.close(None).ok();

    // SIGTERM ends it cleanly.
    nix::sys::signal::kill(
        nix::unistd::Pid::from_raw(view.0.id() as i32),
        Signal::SIGTERM,
    )
    .unwrap();
    let status = exit_within(&mut view.0, Duration::from_secs(10), || {
        "vref view after SIGTERM".to_owned()
    });
    assert_eq!(status.code(), Some(0));
}

#[test]
fn view_help_lists_its_flags_and_bad_input_exits_2() {
    let limit = Duration::from_secs(30);
    let run = support::vref(&["view", "--help"], limit).ok();
    for flag in [
        "--listen",
        "--no-listen",
        "--mcap",
        "--duration",
        "--scene-rate",
        "--answer-rate",
        "--images",
        "--config",
    ] {
        assert!(run.stdout.contains(flag), "view --help lacks {flag}");
    }
    let run = support::vref(&["record", "--help"], limit).ok();
    assert!(run.stdout.contains("FILE.mcap"), "{}", run.stdout);
    assert!(run.stdout.contains("--images"), "{}", run.stdout);

    // Nothing to serve and nothing to write.
    let run = support::vref(&["view", "--no-listen"], limit);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    // A file that cannot be created is named.
    let run = support::vref(
        &[
            "view",
            "--no-listen",
            "--mcap",
            "/nonexistent-dir/x.mcap",
            "--duration",
            "1s",
        ],
        limit,
    );
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(
        run.stderr.contains("/nonexistent-dir/x.mcap"),
        "{}",
        run.stderr
    );
    let run = support::vref(&["view", "--answer-rate", "-1"], limit);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    // Images come from bop:DIR, a folder that exists, and into MCAP only.
    let run = support::vref(&["view", "--images", "/tmp"], limit);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    let run = support::vref(
        &[
            "view",
            "--no-listen",
            "--mcap",
            "/tmp/never-written.mcap",
            "--images",
            "bop:/nonexistent-bop",
        ],
        limit,
    );
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(run.stderr.contains("/nonexistent-bop"), "{}", run.stderr);
    let run = support::vref(
        &[
            "record",
            "--out",
            "/tmp/never-written.vrec",
            "--duration",
            "1s",
            "--images",
            "bop:/nonexistent-bop",
        ],
        limit,
    );
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(run.stderr.contains("MCAP"), "{}", run.stderr);
}

const IMAGE_TOPICS: [(&str, &str); 6] = [
    ("/vref/robot/image", "foxglove.CompressedImage"),
    ("/vref/robot/calibration", "foxglove.CameraCalibration"),
    ("/vref/robot/annotations", "foxglove.ImageAnnotations"),
    ("/vref/human/image", "foxglove.CompressedImage"),
    ("/vref/human/calibration", "foxglove.CameraCalibration"),
    ("/vref/human/annotations", "foxglove.ImageAnnotations"),
];

/// The scene whose `side` objects a raw snapshot carries.
fn scene_of_snapshot(world: &vref_feed::BopWorld, side: Side, data: &[u8]) -> Option<String> {
    let (_, entries): (SnapshotHeader, Vec<ObjectEntry>) = take_sample("snapshot", data).unwrap();
    let first = entries.first()?.track_id;
    world
        .pairs()
        .iter()
        .find(|p| {
            let graph = match side {
                Side::Robot => &p.robot,
                Side::Human => &p.human,
            };
            graph.index_of(first).is_some()
        })
        .map(|p| p.name.clone())
}

#[test]
fn vref_view_images_show_each_bop_scene_fed_with_its_mask_outlines() {
    use foxglove::messages::{CameraCalibration, CompressedImage, ImageAnnotations};

    let table = vref_testkit::data("bop/table");
    let source = format!("bop:{}", table.display());
    let mut h = Harness::new("images", "");
    h.start("matcher", "vref-matcher", &[]);
    for (name, bin) in [
        ("perception", "vref-perception-feed"),
        ("gesture", "vref-gesture-feed"),
    ] {
        // A scene a second, so that a few seconds show several.
        h.start(name, bin, &["--source", &source, "--hold-s", "1"]);
    }
    let config = vref_config::Config::from_file(&h.config).unwrap();
    let mut client = ReferenceClient::connect(&config.ipc, "test-images").unwrap();
    eventually(Duration::from_secs(60), "answers on BOP scenes", || {
        let a = client.latest_gesture(Duration::from_millis(300)).ok()?;
        matches!(a.status(), AnswerStatus::Ok | AnswerStatus::Ambiguous).then_some(())
    });

    let out = h.dir.path().join("bop.mcap");
    let run = support::vref(
        &[
            "view",
            "--no-listen",
            "--images",
            &source,
            "--mcap",
            out.to_str().unwrap(),
            "--duration",
            "4s",
            "--answer-rate",
            "0",
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(120),
    )
    .ok();
    let bytes = std::fs::read(&out).unwrap();

    // The image channels, in Foxglove's schemas, each with messages, as
    // many as the viewer said it wrote.
    let channels = summary(&bytes);
    for (topic, schema) in IMAGE_TOPICS {
        let (encoding, name, schema_encoding, count) = &channels
            .get(topic)
            .unwrap_or_else(|| panic!("no {topic} in {channels:?}"));
        assert_eq!(
            (encoding.as_str(), name.as_str(), schema_encoding.as_str()),
            ("protobuf", schema, "protobuf"),
            "{topic}"
        );
        assert!(*count >= 1, "{topic}: no messages");
    }
    let count = |topic: &str| channels[topic].3;
    assert_eq!(
        count("/vref/robot/image") + count("/vref/human/image"),
        printed(&run.stdout, "images")
    );
    assert_eq!(
        count("/vref/robot/calibration") + count("/vref/human/calibration"),
        printed(&run.stdout, "calibrations")
    );
    assert_eq!(
        count("/vref/robot/annotations") + count("/vref/human/annotations"),
        printed(&run.stdout, "image annotations")
    );

    // The scenes as the feeds measure them: which objects each image has.
    let world =
        vref_feed::BopWorld::load(&table, None, config.perception, config.scene.limits(), 1.0)
            .unwrap();
    let mut latest_snapshot: [Option<String>; 2] = [None, None];
    let mut size: [Option<(u32, u32)>; 2] = [None, None];
    let mut scenes_shown = std::collections::BTreeSet::new();
    let mut checked = [0; 2];
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let message = message.unwrap();
        let topic = message.channel.topic.as_str();
        let (side, k) = if topic.starts_with("/vref/robot/") || topic == "/vref/wire/robot/snapshot"
        {
            (Side::Robot, 0)
        } else if topic.starts_with("/vref/human/") || topic == "/vref/wire/human/snapshot" {
            (Side::Human, 1)
        } else {
            continue;
        };
        let frame = ["robot_camera", "headset_camera"][k];
        match topic.rsplit('/').next().unwrap() {
            "snapshot" => latest_snapshot[k] = scene_of_snapshot(&world, side, &message.data),
            "image" => {
                let image = CompressedImage::decode(&message.data[..]).unwrap();
                assert_eq!(image.format, "jpeg");
                assert_eq!(image.data[..2], [0xff, 0xd8], "{topic}: not JPEG bytes");
                assert_eq!(image.frame_id, frame);
            }
            "calibration" => {
                let c = CameraCalibration::decode(&message.data[..]).unwrap();
                assert_eq!(c.frame_id, frame);
                assert!(c.k[0] > 0.0 && c.k[4] > 0.0, "{c:?}");
                size[k] = Some((c.width, c.height));
            }
            "annotations" => {
                let a = ImageAnnotations::decode(&message.data[..]).unwrap();
                let scene = a
                    .metadata
                    .iter()
                    .find(|m| m.key == "scene")
                    .map(|m| m.value.clone())
                    .unwrap();
                // The image shown is of the scene being fed.
                assert_eq!(Some(&scene), latest_snapshot[k].as_ref(), "{topic}");
                let (pair, source) = world
                    .pairs()
                    .iter()
                    .zip(world.sources())
                    .find(|(p, _)| p.name == scene)
                    .unwrap();
                let (objects, image) = match side {
                    Side::Robot => (pair.robot.objects(), &source.robot),
                    Side::Human => (pair.human.objects(), &source.human),
                };
                // One outline and one label per object the feed publishes.
                assert_eq!(a.points.len(), objects.len(), "{scene} {topic}");
                assert_eq!(a.texts.len(), objects.len(), "{scene} {topic}");
                let mut ids: Vec<u64> = a
                    .points
                    .iter()
                    .map(|p| p.metadata[0].value.parse().unwrap())
                    .collect();
                ids.sort_unstable();
                let mut want: Vec<u64> = image.track_ids.iter().flatten().copied().collect();
                want.sort_unstable();
                assert_eq!(ids, want, "{scene} {topic}");
                let (w, h) = size[k].expect("a calibration before the annotations");
                for outline in &a.points {
                    assert!(outline.points.len() >= 8, "{scene}: {outline:?}");
                    assert_eq!(outline.points.len() % 2, 0, "segments come in pairs");
                    for p in &outline.points {
                        assert!(
                            (0.0..=f64::from(w)).contains(&p.x)
                                && (0.0..=f64::from(h)).contains(&p.y),
                            "{scene}: ({}, {}) off the {w}x{h} image",
                            p.x,
                            p.y
                        );
                    }
                }
                scenes_shown.insert((k, scene));
                checked[k] += 1;
            }
            _ => {}
        }
    }
    assert!(checked[0] >= 1 && checked[1] >= 1, "{checked:?}");
    // The feeds moved on a scene a second: the images followed.
    let robot_scenes = scenes_shown.iter().filter(|(k, _)| *k == 0).count();
    assert!(robot_scenes >= 2, "{scenes_shown:?}");

    let topics: Vec<&str> = IMAGE_TOPICS.iter().map(|(t, _)| *t).collect();
    python_reads(&out, &topics, "foxglove.ImageAnnotations");
}
