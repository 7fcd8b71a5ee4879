//! vref's ROS 2 tools with real ROS 2 software on the other side:
//! rosbag2 files in and out, written and read by the Python `rosbags`
//! package (pure Python, no ROS install, independent of vref), the
//! feeds on `--source rosbag:FILE.mcap`, the refusals of files that
//! cannot be a camera, `vref record --ros2` read back by rosbags and
//! rclpy, and `vref bench ros2` against rclpy nodes. tools/test.sh
//! installs rosbags and rclpy in target/ros2-venv and names that python in
//! `VREF_ROS2_PYTHON`. Every wait on another process is bounded.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use vref_testkit::repo_root;
use vref_testkit::{Harness, eventually};
use vref_wire::AnswerStatus;
use vref_wire::ipc::ReferenceClient;

/// Hang guard for one feed that is expected to refuse its source.
const REFUSAL_LIMIT: Duration = Duration::from_secs(60);

/// Both cameras are OSD's Kinect (as in tests/camera.rs), and the bags
/// carry the scene's instance labels on a labels topic.
const CONFIG: &str = "\n[perception.human]\npixel = { a = 0.0, b = 0.0, c = 0.0025 }\nsystematic = { a = 0.0, b = 0.005, c = 0.0 }\n\n[ros2]\nlabels_topic = \"/camera/camera/labels\"\n";

fn python() -> String {
    std::env::var("VREF_ROS2_PYTHON").unwrap_or_else(|_| {
        panic!(
            "VREF_ROS2_PYTHON is not set: run tools/test.sh, which installs rosbags in target/ros2-venv"
        )
    })
}

/// OSD scene `name` as raw buffers (rgb8, u16 mm depth, u16 labels) and
/// its camera, for rosbag_writer.py.
fn write_scene(dir: &Path, name: &str) {
    let scene = vref_testkit::data("osd/learn").join(name);
    assert!(scene.exists(), "OSD data not found at {}", scene.display());
    std::fs::create_dir_all(dir).unwrap();
    let limit = vref_perception::ImageLimit::default();
    let colour = vref_perception::load_colour(&scene.join("rgb.png"), limit).unwrap();
    let depth = vref_perception::load_depth(&scene.join("depth.png"), limit).unwrap();
    let labels = vref_perception::load_depth(&scene.join("label.png"), limit).unwrap();
    let camera: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(vref_testkit::data("osd/camera.json")).unwrap(),
    )
    .unwrap();
    std::fs::write(dir.join("rgb.raw"), colour.as_raw()).unwrap();
    let le = |v: &[u16]| v.iter().flat_map(|d| d.to_le_bytes()).collect::<Vec<u8>>();
    std::fs::write(dir.join("depth.raw"), le(depth.as_raw())).unwrap();
    std::fs::write(dir.join("labels.raw"), le(labels.as_raw())).unwrap();
    let frame = serde_json::json!({
        "width": colour.width(), "height": colour.height(),
        "fx": camera["fx"], "fy": camera["fy"], "cx": camera["cx"], "cy": camera["cy"],
    });
    std::fs::write(dir.join("frame.json"), frame.to_string()).unwrap();
}

/// Runs rosbag_writer.py; the path of the .mcap file it wrote.
fn write_bag(scene: &Path, out: &Path, args: &[&str]) -> PathBuf {
    let script = repo_root().join("tests/rosbag_writer.py");
    let mut child = Command::new(python())
        .arg(&script)
        .arg("--scene")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starting the rosbags writer");
    // Hang guard: writing five 640x480 frames takes about a second.
    let finished = eventually(Duration::from_secs(120), "the rosbags writer", || {
        child.try_wait().unwrap()
    });
    let out = child.wait_with_output().unwrap();
    assert!(
        finished.success(),
        "rosbag_writer.py {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    PathBuf::from(String::from_utf8(out.stdout).unwrap().trim())
}

#[test]
fn feeds_on_bags_written_by_rosbags_publish_objects_that_the_matcher_matches() {
    let mut h = Harness::new("bag", CONFIG);
    let scene = h.dir.path().join("scene");
    write_scene(&scene, "learn3");
    // The robot's bag in rgb8 and 16-bit millimetres, the headset's in
    // bgr8 and 32-bit float metres: the same frames once decoded.
    let robot = write_bag(
        &scene,
        &h.dir.path().join("robot_bag"),
        &["--labels", "--frames", "5"],
    );
    let headset = write_bag(
        &scene,
        &h.dir.path().join("headset_bag"),
        &[
            "--labels",
            "--frames",
            "5",
            "--colour-encoding",
            "bgr8",
            "--depth-encoding",
            "32FC1",
        ],
    );
    h.start("matcher", "vref-matcher", &[]);
    for (name, bin, bag) in [
        ("perception", "vref-perception-feed", &robot),
        ("gesture", "vref-gesture-feed", &headset),
    ] {
        let source = format!("rosbag:{}", bag.display());
        h.start(name, bin, &["--source", &source]);
    }
    let config = vref_config::Config::from_file(&h.config).unwrap();
    let mut client = ReferenceClient::connect(&config.ipc, "test-client").unwrap();
    // Both views are the same labelled frames: label 1 is matched to itself.
    let answer = eventually(Duration::from_secs(60), "an ok answer for label 1", || {
        let a = client.by_human_object(1, Duration::from_millis(500)).ok()?;
        (a.status() == AnswerStatus::Ok).then_some(a)
    });
    assert_eq!(answer.robot_track_id, 1);
    for name in ["perception", "gesture"] {
        assert!(h.running(name), "{name}: {}", h.log(name));
        let log = h.log(name);
        assert!(
            log.contains("5 frames with objects of 5 paired")
                && log.contains("messages colour 5, depth 5, labels 5"),
            "{name}: {log}"
        );
    }
}

/// Without a labels topic vref's segmenter labels each frame of the bag,
/// as vref-ros2 does with live topics.
#[test]
fn a_bag_without_labels_is_segmented() {
    let kinect = CONFIG.split("[ros2]").next().unwrap();
    let mut h = Harness::new("bagseg", kinect);
    let scene = h.dir.path().join("scene");
    write_scene(&scene, "learn3");
    let bag = write_bag(&scene, &h.dir.path().join("bag"), &["--frames", "3"]);
    let source = format!("rosbag:{}", bag.display());
    h.start("perception", "vref-perception-feed", &["--source", &source]);
    let log = eventually(Duration::from_secs(60), "the feed publishing", || {
        let log = h.log("perception");
        log.contains("publishing").then_some(log)
    });
    assert!(h.running("perception"), "{log}");
    assert!(
        log.contains("3 frames with objects of 3 paired")
            && log.contains("messages colour 3, depth 3;"),
        "{log}"
    );
}

/// Starts the perception feed on `source` and expects it to refuse it
/// (exit code 2) with every one of `expected` in its log.
fn refused(h: &mut Harness, name: &str, source: &str, expected: &[&str]) {
    let source = format!("rosbag:{source}");
    h.start(name, "vref-perception-feed", &["--source", &source]);
    let status = h.wait(name, REFUSAL_LIMIT);
    let log = h.log(name);
    assert_eq!(status.code(), Some(2), "{name}: {log}");
    for e in expected {
        assert!(log.contains(e), "{name}: no {e:?} in\n{log}");
    }
}

#[test]
fn files_that_cannot_be_a_camera_are_refused_naming_why() {
    let mut h = Harness::new("badbag", CONFIG);
    let dir = h.dir.path().to_owned();
    let scene = dir.join("scene");
    write_scene(&scene, "learn3");

    let missing = dir.join("missing.mcap");
    refused(
        &mut h,
        "missing",
        missing.to_str().unwrap(),
        &["cannot read", "missing.mcap"],
    );

    let text = dir.join("notes.mcap");
    std::fs::write(&text, "not a bag\n").unwrap();
    refused(
        &mut h,
        "not_mcap",
        text.to_str().unwrap(),
        &["is not an MCAP file"],
    );

    let other = write_bag(
        &scene,
        &dir.join("other_topics"),
        &["--labels", "--frames", "2", "--prefix", "/other"],
    );
    refused(
        &mut h,
        "topic",
        other.to_str().unwrap(),
        &[
            "no messages on topic /camera/camera/color/image_raw",
            "topics with messages: /other/aligned_depth_to_color/image_raw (sensor_msgs/msg/Image)",
            "/other/color/camera_info (sensor_msgs/msg/CameraInfo)",
        ],
    );

    let no_labels = write_bag(&scene, &dir.join("no_labels"), &["--frames", "2"]);
    refused(
        &mut h,
        "labels",
        no_labels.to_str().unwrap(),
        &["no messages on topic /camera/camera/labels (labels)"],
    );

    let json = write_bag(
        &scene,
        &dir.join("json"),
        &["--labels", "--frames", "2", "--serialization", "json"],
    );
    refused(
        &mut h,
        "message_encoding",
        json.to_str().unwrap(),
        &["has message encoding \"json\"; only cdr (ROS 2's) is read"],
    );

    let yuv = write_bag(
        &scene,
        &dir.join("yuv"),
        &["--labels", "--frames", "2", "--colour-encoding", "yuv422"],
    );
    refused(
        &mut h,
        "encoding",
        yuv.to_str().unwrap(),
        &[
            "message 0 on /camera/camera/color/image_raw",
            "encoding \"yuv422\" is not supported for colour (supported: rgb8, bgr8, rgba8, bgra8)",
        ],
    );
}

/// `vref record --ros2` next to the synthetic feeds (which point, so the
/// matcher has answers), read back by rosbags and by rclpy's deserializer.
#[test]
fn record_ros2_writes_a_bag_that_rosbags_and_rclpy_read() {
    let mut h = Harness::new("recros2", "");
    h.start("matcher", "vref-matcher", &[]);
    for (name, bin) in [
        ("perception", "vref-perception-feed"),
        ("gesture", "vref-gesture-feed"),
    ] {
        h.start(name, bin, &["--rate", "30"]);
    }
    let config = vref_config::Config::from_file(&h.config).unwrap();
    let mut client = ReferenceClient::connect(&config.ipc, "test-client").unwrap();
    eventually(
        Duration::from_secs(60),
        "an ok latest-gesture answer",
        || {
            let a = client.latest_gesture(Duration::from_millis(500)).ok()?;
            (a.status() == AnswerStatus::Ok).then_some(())
        },
    );
    let out = h.dir.path().join("vref-ros2.mcap");
    let run = support::vref(
        &[
            "record",
            "--ros2",
            out.to_str().unwrap(),
            "--duration",
            "4s",
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(60),
    );
    assert_eq!(run.code, Some(0), "{}\n{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("marker arrays"), "{}", run.stdout);

    let script = repo_root().join("tests/rosbag_reader.py");
    let mut child = Command::new(python())
        .arg(&script)
        .arg(&out)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starting the rosbags reader");
    let status = eventually(Duration::from_secs(120), "the rosbags reader", || {
        child.try_wait().unwrap()
    });
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(status.success(), "rosbag_reader.py failed: {stderr}");
    let found: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    println!("{}", found["topics"]);
    assert_eq!(found["rclpy"], true, "rclpy did not deserialize: {stderr}");
    let s = &config.ros2;
    for (topic, msgtype, durability) in [
        (
            &s.markers_topic,
            "visualization_msgs/msg/MarkerArray",
            "volatile",
        ),
        (
            &s.referenced_object_topic,
            "geometry_msgs/msg/PointStamped",
            "transient_local",
        ),
        (
            &s.headset_pose_topic,
            "geometry_msgs/msg/PoseStamped",
            "volatile",
        ),
    ] {
        let t = &found["topics"][topic.as_str()];
        assert_eq!(t["msgtype"], msgtype, "{topic}: {found}");
        assert_eq!(t["serialization_format"], "cdr", "{topic}: {found}");
        assert_eq!(t["msgdef_format"], "msg", "{topic}: {found}");
        assert_eq!(t["durability"], serde_json::json!([durability]), "{topic}");
        assert_eq!(t["reliability"], serde_json::json!(["reliable"]), "{topic}");
        assert!(t["count"].as_u64().unwrap() >= 1, "{topic}: {found}");
    }
    for ns in ["robot", "human"] {
        assert!(found["namespaces"][ns].as_u64().unwrap_or(0) > 0, "{found}");
    }
    let point = &found["points"][0];
    assert_eq!(point["frame_id"], s.robot_frame_id.as_str());
    let p: Vec<f64> = serde_json::from_value(point["point"].clone()).unwrap();
    assert!(p.iter().all(|v| v.is_finite()), "{point}");
    for pose in found["poses"].as_array().unwrap() {
        assert_eq!(pose["frame_id"], s.robot_frame_id.as_str());
        let norm = pose["quaternion_norm"].as_f64().unwrap();
        assert!((norm - 1.0).abs() < 1e-6, "{pose}");
    }
}

/// `vref bench ros2` for a few seconds: it runs (in its own namespace),
/// its JSON line has the documented fields, and frames went through.
/// No timing is asserted.
#[test]
fn bench_ros2_reports_latency_beside_the_dds_floor() {
    let frame = vref_testkit::data("osd/learn/learn3");
    let python = python();
    let run = support::vref(
        &[
            "bench",
            "ros2",
            "--seconds",
            "3",
            "--json",
            "--frame",
            frame.to_str().unwrap(),
            "--python",
            &python,
        ],
        // Hang guard: warm-up is bounded by the peer at 60 s.
        Duration::from_secs(300),
    );
    assert_eq!(run.code, Some(0), "{}\n{}", run.stdout, run.stderr);
    let lines = support::json_lines(&run.stdout);
    assert_eq!(lines.len(), 1, "{}", run.stdout);
    let r = &lines[0];
    println!("{r}");
    let frames = r["frames"].as_u64().unwrap();
    assert!(frames > 0, "{r}");
    for field in ["p50_ms", "p99_ms", "floor_p50_ms", "floor_p99_ms"] {
        assert!(r[field].as_f64().is_some_and(|v| v >= 0.0), "{field}: {r}");
    }
    assert!(r["dropped"].as_u64().unwrap() < frames, "{r}");
    assert!(r["rss_end_kb"].as_u64().unwrap() > 0, "{r}");
}
