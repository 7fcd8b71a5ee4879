//! The command-line checks both feed binaries share; each feed package's
//! tests/cli.rs passes its binary (having integration tests is what makes
//! `cargo test` build a package's binary).

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use vref_scene::Side;
use vref_wire::ipc::{IpcSettings, SnapshotWatch};

use crate::wait::{eventually, exit_within};

fn run(bin: &str, args: &[&str], dir: &Path) -> Output {
    Command::new(bin)
        .args(args)
        .current_dir(dir)
        .env_remove("VREF_CONFIG")
        .output()
        .unwrap()
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// `--help` lists every flag and source kind.
pub fn help_lists_every_flag(bin: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = run(bin, &["--help"], dir.path());
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--config",
        "--source",
        "--rate",
        "--objects",
        "--epoch-ns",
        "--hold",
        "dataset:FILE",
        "recording:FILE",
    ] {
        assert!(text.contains(flag), "--help lacks {flag}:\n{text}");
    }
}

/// Bad sources, rates and presets exit 2 naming the problem.
pub fn bad_sources_and_settings_exit_2_naming_the_problem(bin: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = run(bin, &["--source", "webcam"], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("webcam"), "{}", stderr(&out));

    let out = run(bin, &["--source", "dataset:no-such.jsonl"], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no-such.jsonl"), "{}", stderr(&out));

    let out = run(bin, &["--rate", "0"], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--rate"), "{}", stderr(&out));

    let config = dir.path().join("bad.toml");
    std::fs::write(&config, "[feeds]\npreset = \"kitchen\"\n").unwrap();
    let out = run(bin, &["--config", config.to_str().unwrap()], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("kitchen"), "{}", stderr(&out));
}

/// Snapshots the feed publishes before it is stopped: 1.5 s of its own
/// 50 Hz clock, however slowly the machine started it.
const SNAPSHOTS_BEFORE_STOP: u64 = 75;

/// Runs the feed at 50 Hz under its own root path and prefix
/// (`prefix_tag`) until `side`'s snapshots have reached
/// [`SNAPSHOTS_BEFORE_STOP`], stops it with SIGTERM, checks exit 0, that
/// its start line names `frame` and that it published; returns its log.
pub fn publishes_until_sigterm_then_exits_0(
    bin: &str,
    prefix_tag: &str,
    frame: &str,
    side: Side,
) -> String {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("iox");
    std::fs::create_dir(&root).unwrap();
    let config = dir.path().join("vref.toml");
    let prefix = format!("{prefix_tag}{}_", std::process::id());
    std::fs::write(
        &config,
        format!(
            "[ipc]\nroot_path = \"{}\"\nprefix = \"{prefix}\"\n",
            root.display()
        ),
    )
    .unwrap();
    let mut child = Command::new(bin)
        .args(["--config", config.to_str().unwrap(), "--rate", "50"])
        .current_dir(dir.path())
        .env_remove("VREF_CONFIG")
        .env("RUST_LOG", "info")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let settings = IpcSettings {
        root_path: Some(root.clone()),
        prefix: prefix.clone(),
        ..IpcSettings::default()
    };
    let watch = SnapshotWatch::connect(&settings, side, &format!("{prefix}watch")).unwrap();
    let mut newest = 0;
    eventually(Duration::from_secs(30), "the feed's snapshots", || {
        if let Some(header) = watch.latest().unwrap() {
            newest = header.sequence;
        }
        (newest >= SNAPSHOTS_BEFORE_STOP).then_some(())
    });
    drop(watch);
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    exit_within(&mut child, Duration::from_secs(10), || {
        format!("{bin} after SIGTERM")
    });
    let out = child.wait_with_output().unwrap();
    let log = stderr(&out);
    assert_eq!(out.status.code(), Some(0), "{log}");
    assert!(out.stdout.is_empty());
    assert!(log.contains(frame) && log.contains("50"), "{log}");
    assert!(count_in(&log, "snapshots") > 0, "{log}");
    log
}

/// The count `key=N` of a feed's stop line in `log`.
pub fn count_in(log: &str, key: &str) -> u64 {
    log.split(&format!("{key}="))
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no {key}= in\n{log}"))
}
