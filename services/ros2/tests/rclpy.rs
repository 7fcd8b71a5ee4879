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

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

/// A child killed when the test ends, whichever way.
struct Guard(Child);

impl Drop for Guard {
    fn drop(&mut self) {
        self.0.kill().ok();
        self.0.wait().ok();
    }
}

/// One OSD scene as the raw buffers a camera driver would send.
fn write_scene(dir: &Path) {
    let scene = repo().join("../shared/data/osd/learn/learn3");
    assert!(scene.exists(), "OSD data not found at {}", scene.display());
    let colour = vref_perception::load_colour(&scene.join("rgb.png")).unwrap();
    let depth = vref_perception::load_depth(&scene.join("depth.png")).unwrap();
    let camera: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(repo().join("../shared/data/osd/camera.json")).unwrap(),
    )
    .unwrap();
    std::fs::write(dir.join("rgb.raw"), colour.as_raw()).unwrap();
    let bytes: Vec<u8> = depth
        .as_raw()
        .iter()
        .flat_map(|d| d.to_le_bytes())
        .collect();
    std::fs::write(dir.join("depth.raw"), bytes).unwrap();
    let frame = serde_json::json!({
        "width": colour.width(), "height": colour.height(),
        "fx": camera["fx"], "fy": camera["fy"], "cx": camera["cx"], "cy": camera["cy"],
    });
    std::fs::write(dir.join("frame.json"), frame.to_string()).unwrap();
}

#[test]
fn rclpy_camera_gets_markers_and_answers_and_malformed_messages_are_skipped() {
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
            "[ipc]\nroot_path = \"{}\"\nprefix = \"r{}_\"\n",
            root.display(),
            std::process::id()
        ),
    )
    .unwrap();
    write_scene(dir.path());
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_vref-ros2"));
    let matcher = bin.parent().unwrap().join("vref-matcher");
    assert!(
        matcher.exists(),
        "{} not built: run tools/test.sh",
        matcher.display()
    );
    let matcher_log = std::fs::File::create(dir.path().join("matcher.log")).unwrap();
    let _matcher = Guard(
        Command::new(&matcher)
            .arg("--config")
            .arg(&config)
            .stdin(Stdio::null())
            .stdout(matcher_log.try_clone().unwrap())
            .stderr(matcher_log)
            .spawn()
            .unwrap(),
    );

    let ros_log = dir.path().join("vref-ros2.log");
    let peer = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/rclpy_peer.py");
    // A network namespace with loopback only, and multicast routed on it
    // (DDS discovery is multicast); the peer starts vref-ros2 inside it.
    let mut child = Guard(
        Command::new("unshare")
            .args([
                "--net",
                "--",
                "sh",
                "-c",
                "ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec \"$@\"",
                "sh",
            ])
            .arg(&python)
            .arg(&peer)
            .arg("--vref-ros2")
            .arg(&bin)
            .arg("--config")
            .arg(&config)
            .arg("--scene")
            .arg(dir.path())
            .arg("--log")
            .arg(&ros_log)
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
