//! The matcher binary as an operator meets it. (Having an integration test
//! also makes `cargo test --workspace` build the binary, which the system
//! tests, package vref-system-tests in tests/, start.)
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::process::{Command, Stdio};
use std::time::Duration;

use nix::sys::signal::Signal;
use vref_testkit::{Harness, eventually};

fn matcher() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_vref-matcher"));
    command
        .env_remove("VREF_CONFIG")
        .env("RUST_LOG", "info")
        .stdin(Stdio::null());
    command
}

#[test]
fn help_names_the_config_flag() {
    let out = matcher().arg("--help").output().unwrap();
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("--config"));
}

#[test]
fn a_bad_configuration_exits_2_naming_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("[matcher]\nmethod = \"magic\"\n", "magic"),
        ("[matcher]\nstale_after = 5\n", "stale_after"),
        ("[ipc]\nprefix = \"\"\n", "prefix"),
    ];
    for (text, needle) in cases {
        let file = dir.path().join("bad.toml");
        std::fs::write(&file, text).unwrap();
        let out = matcher().arg("--config").arg(&file).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{text}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(needle), "{text}: {stderr}");
    }
}

#[test]
fn sigterm_stops_it_with_exit_0() {
    let mut harness = Harness::new("mcli", "");
    harness.start("matcher", "vref-matcher", &[]);
    eventually(Duration::from_secs(20), "matcher ready", || {
        harness
            .log("matcher")
            .contains("matcher ready")
            .then_some(())
    });
    harness.signal("matcher", Signal::SIGTERM);
    let status = harness.wait("matcher", Duration::from_secs(10));
    assert_eq!(status.code(), Some(0));
    let text = harness.log("matcher");
    assert!(text.contains("matcher stopped"), "{text}");
}
