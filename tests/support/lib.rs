//! Shared by the system tests (processes, waits, executables and data
//! are vref-testkit's): the `vref` command with a time limit, the table
//! scene, a robot and a headset on either side of Zenoh.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub mod remote;
pub mod table;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

/// What a finished command left behind.
#[derive(Debug)]
pub struct Run {
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    /// Panics with the command's stderr unless it exited 0.
    pub fn ok(self) -> Self {
        assert_eq!(self.code, Some(0), "command failed:\n{}", self.stderr);
        self
    }
}

/// CMU House in the shared data (`VREF_DATA`); `VREF_CMU_HOUSE` overrides.
pub fn cmu_house_dir() -> PathBuf {
    let dir = std::env::var_os("VREF_CMU_HOUSE")
        .map(PathBuf::from)
        .unwrap_or_else(|| vref_testkit::data("cmu_house"));
    assert!(
        dir.join("label/house1").exists(),
        "CMU House data not found at {}",
        dir.display()
    );
    dir
}

/// Runs `vref` with `args` and the repository's config, killing it after
/// `limit` so that a hang fails the test instead of stalling the suite.
pub fn vref(args: &[&str], limit: Duration) -> Run {
    vref_at(&vref_testkit::binary("vref"), args, limit)
}

/// Like [`vref`], with the `vref` binary at `program` (a copy beside
/// other service binaries, say).
pub fn vref_at(program: &Path, args: &[&str], limit: Duration) -> Run {
    vref_with(program, args, &[], limit)
}

/// Like [`vref_at`], with environment variables `env` set.
pub fn vref_with(program: &Path, args: &[&str], env: &[(&str, &str)], limit: Duration) -> Run {
    let config = vref_testkit::repo_root().join("config/vref.toml");
    // The caller's `env` last: it may set what the defaults clear.
    let mut child = Command::new(program)
        .args(args)
        .env("VREF_CONFIG", &config)
        .env_remove("RUST_LOG")
        .envs(env.iter().copied())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start vref");
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut text = String::new();
            pipe.read_to_string(&mut text).ok();
            text
        })
    };
    let stdout = drain(Box::new(child.stdout.take().unwrap()));
    let stderr = drain(Box::new(child.stderr.take().unwrap()));
    let status = vref_testkit::exit_within(&mut child, limit, || format!("vref {args:?}"));
    Run {
        code: status.code(),
        stdout: stdout.join().unwrap(),
        stderr: stderr.join().unwrap(),
    }
}

/// Parses the one-JSON-object-per-line output of `--json`.
pub fn json_lines(stdout: &str) -> Vec<serde_json::Value> {
    stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON: {l:?}: {e}")))
        .collect()
}
