//! vref-ros2 against a genuine ROS 2 node: rclpy from the official ROS 2
//! wheels (tools/test.sh installs them in target/ros2-venv and names its
//! python in `VREF_ROS2_PYTHON`), inside a network namespace of its own
//! with only loopback up, so that DDS discovery never leaves the machine.
//! The checks themselves are in rclpy_peer.py (next to this file).
//!
//! No fallback: where the namespace cannot be made (not root, no
//! `unshare`), or the venv is missing, the test fails and says why.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The whole exchange, start-up included, must end within this.
const LIMIT: Duration = Duration::from_secs(120);

/// A child killed when the test ends, whichever way.
struct Guard(Child);

impl Drop for Guard {
    fn drop(&mut self) {
        self.0.kill().ok();
        self.0.wait().ok();
    }
}

/// One OSD scene as the raw buffers a camera driver would send, with its
/// instance labels (u16, 0 background).
fn write_scene(dir: &Path, name: &str) {
    let scene = vref_testkit::data("osd/learn").join(name);
    assert!(scene.exists(), "OSD data not found at {}", scene.display());
    let colour = vref_perception::load_colour(
        &scene.join("rgb.png"),
        vref_perception::ImageLimit::default(),
    )
    .unwrap();
    let depth = vref_perception::load_depth(
        &scene.join("depth.png"),
        vref_perception::ImageLimit::default(),
    )
    .unwrap();
    let camera: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(vref_testkit::data("osd/camera.json")).unwrap(),
    )
    .unwrap();
    std::fs::write(dir.join("rgb.raw"), colour.as_raw()).unwrap();
    let bytes: Vec<u8> = depth
        .as_raw()
        .iter()
        .flat_map(|d| d.to_le_bytes())
        .collect();
    std::fs::write(dir.join("depth.raw"), bytes).unwrap();
    let labels = vref_perception::load_depth(
        &scene.join("label.png"),
        vref_perception::ImageLimit::default(),
    )
    .unwrap();
    let bytes: Vec<u8> = labels
        .as_raw()
        .iter()
        .flat_map(|d| d.to_le_bytes())
        .collect();
    std::fs::write(dir.join("labels.raw"), bytes).unwrap();
    let frame = serde_json::json!({
        "width": colour.width(), "height": colour.height(),
        "fx": camera["fx"], "fy": camera["fy"], "cx": camera["cx"], "cy": camera["cy"],
    });
    std::fs::write(dir.join("frame.json"), frame.to_string()).unwrap();
}

#[test]
fn rclpy_camera_gets_markers_and_answers_and_malformed_messages_are_skipped() {
    run_peer("learn3", "", &["--stop-matcher"]);
}

/// The headset's camera and a pointing pose over ROS 2 too: the same OSD
/// scene from both cameras, with its own labels on both.
#[test]
fn rclpy_headset_pointing_gets_an_ok_answer_a_point_and_the_headset_pose() {
    let topics = "\
[ros2]
labels_topic = \"/camera/camera/labels\"
headset_colour_topic = \"/headset/color/image_raw\"
headset_depth_topic = \"/headset/depth/image_raw\"
headset_camera_info_topic = \"/headset/color/camera_info\"
headset_labels_topic = \"/headset/labels\"
pointing_topic = \"/headset/pointing\"
pointing_cone_deg = 3.0
";
    run_peer("learn20", topics, &["--pointing"]);
}

/// Runs rclpy_peer.py (and, from it, vref-ros2) in a loopback-only network
/// namespace, with a matcher, on OSD scene `scene`; `extra` is appended to
/// the configuration. `--stop-matcher` hands the peer the matcher's pid,
/// which it stops (SIGSTOP) for a while and continues.
fn run_peer(scene: &str, extra: &str, peer_args: &[&str]) {
    let python = std::env::var("VREF_ROS2_PYTHON").unwrap_or_else(|_| {
        panic!("VREF_ROS2_PYTHON is not set: run tools/test.sh, which installs rclpy in target/ros2-venv")
    });
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("iox");
    std::fs::create_dir_all(&root).unwrap();
    let config = dir.path().join("vref.toml");
    std::fs::write(
        &config,
        format!(
            "[ipc]\nroot_path = \"{}\"\nprefix = \"r{}{}_\"\n{extra}",
            root.display(),
            std::process::id(),
            peer_args.len()
        ),
    )
    .unwrap();
    write_scene(dir.path(), scene);
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_vref-ros2"));
    let matcher = bin.parent().unwrap().join("vref-matcher");
    assert!(
        matcher.exists(),
        "{} not built: run tools/test.sh",
        matcher.display()
    );
    let matcher_log = std::fs::File::create(dir.path().join("matcher.log")).unwrap();
    let matcher = Guard(
        Command::new(&matcher)
            .arg("--config")
            .arg(&config)
            .stdin(Stdio::null())
            .stdout(matcher_log.try_clone().unwrap())
            .stderr(matcher_log)
            .spawn()
            .unwrap(),
    );

    let matcher_pid = matcher.0.id();
    let ros_log = dir.path().join("vref-ros2.log");
    let peer = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/rclpy_peer.py");
    // A network namespace with loopback only, and multicast routed on it
    // (DDS discovery is multicast); the peer starts vref-ros2 inside it.
    let mut child = Guard(
        vref_harness::netns::in_loopback_namespace(Path::new(&python))
            .arg(&peer)
            .arg("--vref-ros2")
            .arg(&bin)
            .arg("--config")
            .arg(&config)
            .arg("--scene")
            .arg(dir.path())
            .arg("--log")
            .arg(&ros_log)
            .args(peer_args.iter().filter(|a| **a != "--stop-matcher"))
            .args(
                peer_args
                    .contains(&"--stop-matcher")
                    .then(|| ["--matcher-pid".to_owned(), matcher_pid.to_string()])
                    .into_iter()
                    .flatten(),
            )
            .env("ROS_DOMAIN_ID", "17")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("starting unshare (util-linux) for the network namespace"),
    );
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut text = String::new();
            pipe.read_to_string(&mut text).ok();
            text
        })
    };
    let out = drain(Box::new(child.0.stdout.take().unwrap()));
    let err = drain(Box::new(child.0.stderr.take().unwrap()));
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.0.try_wait().unwrap() {
            break Some(status);
        }
        if started.elapsed() > LIMIT {
            break None;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    if status.is_none() {
        child.0.kill().ok();
    }
    let (out, err) = (out.join().unwrap(), err.join().unwrap());
    let log = std::fs::read_to_string(&ros_log).unwrap_or_default();
    let tail: String = log
        .lines()
        .rev()
        .take(40)
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect::<Vec<_>>()
        .join("\n");
    let Some(status) = status else {
        panic!("the rclpy peer did not finish within {LIMIT:?}\n{out}\n{err}\nvref-ros2:\n{tail}");
    };
    assert!(
        status.success(),
        "the rclpy peer failed ({status}); a namespace that could not be made fails here too \
         (root and util-linux unshare are needed):\nstdout: {out}\nstderr: {err}\nvref-ros2:\n{tail}"
    );
    println!("{out}");
}
