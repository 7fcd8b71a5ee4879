#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! `vref-perception-feed` as a user meets it: help, refusals with exit
//! code 2, and a clean stop on SIGTERM.

use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_vref-perception-feed");

fn run(args: &[&str], dir: &Path) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .env_remove("VREF_CONFIG")
        .output()
        .unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn help_lists_every_flag() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(&["--help"], dir.path());
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--config",
        "--source",
        "--rate",
        "--objects",
        "--epoch-ns",
        "--hold-s",
        "dataset:FILE",
        "recording:FILE",
    ] {
        assert!(text.contains(flag), "--help lacks {flag}:\n{text}");
    }
}

#[test]
fn bad_sources_and_settings_exit_2_naming_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(&["--source", "webcam"], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("webcam"), "{}", stderr(&out));

    let out = run(&["--source", "dataset:no-such.jsonl"], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no-such.jsonl"), "{}", stderr(&out));

    let out = run(&["--rate", "0"], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--rate"), "{}", stderr(&out));

    let config = dir.path().join("bad.toml");
    std::fs::write(&config, "[feeds]\npreset = \"kitchen\"\n").unwrap();
    let out = run(&["--config", config.to_str().unwrap()], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("kitchen"), "{}", stderr(&out));
}

/// Waits for `child` to exit, killing it after `limit`.
fn wait(mut child: Child, limit: Duration) -> Output {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            child.kill().unwrap();
            panic!("did not stop within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn it_publishes_until_sigterm_then_exits_0() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("iox");
    std::fs::create_dir(&root).unwrap();
    let config = dir.path().join("vref.toml");
    let prefix = format!("pf{}_", std::process::id());
    std::fs::write(
        &config,
        format!(
            "[ipc]\nroot_path = \"{}\"\nprefix = \"{prefix}\"\n",
            root.display()
        ),
    )
    .unwrap();
    let child = Command::new(BIN)
        .args(["--config", config.to_str().unwrap(), "--rate", "50"])
        .current_dir(dir.path())
        .env_remove("VREF_CONFIG")
        .env("RUST_LOG", "info")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let out = wait(child, Duration::from_secs(10));
    let log = stderr(&out);
    assert_eq!(out.status.code(), Some(0), "{log}");
    assert!(out.stdout.is_empty());
    assert!(log.contains("robot_camera") && log.contains("50"), "{log}");
    let published: u64 = log
        .split("snapshots=")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no stop line in\n{log}"));
    assert!(published > 0, "{log}");
}
