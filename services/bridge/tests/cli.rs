//! `vref-bridge` as an operator meets it: help and a usage error. (Having
//! an integration test also makes `cargo test --workspace` build the
//! binary, which the system tests start.)
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::process::{Command, Output};

fn bridge(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vref-bridge"))
        .args(args)
        .env_remove("VREF_CONFIG")
        .output()
        .unwrap()
}

#[test]
fn help_names_the_command_its_config_flag_and_exit_codes() {
    let out = bridge(&["--help"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for part in ["vref-bridge", "--config", "Exit codes"] {
        assert!(text.contains(part), "--help lacks {part}:\n{text}");
    }
}

#[test]
fn an_unknown_flag_exits_2_naming_it() {
    let out = bridge(&["--listen-everywhere"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("--listen-everywhere"), "{stderr}");
}
