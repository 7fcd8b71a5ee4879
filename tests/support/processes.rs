//! Real service processes for system tests: each harness has its own
//! iceoryx2 root path and prefix, so tests never see each other.
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;

/// A binary built beside `vref` (cargo test --workspace builds them all).
pub fn binary(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_BIN_EXE_vref")).parent().unwrap();
    let path = dir.join(name);
    assert!(
        path.exists(),
        "{} not built: run `cargo test --workspace`",
        path.display()
    );
    path
}

/// Processes under test and the files they share.
pub struct Harness {
    pub dir: tempfile::TempDir,
    pub config: PathBuf,
    children: Vec<(String, Child)>,
}

impl Harness {
    /// `extra` is appended to the harness's configuration file.
    pub fn new(tag: &str, extra: &str) -> Self {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("iox");
        std::fs::create_dir_all(&root).unwrap();
        let config = dir.path().join("vref.toml");
        let prefix = format!("t{}{tag}_", std::process::id());
        let text = format!(
            "[ipc]\nroot_path = \"{}\"\nprefix = \"{prefix}\"\n\n[matcher]\nstale_after_ms = 300\ncleanup_interval_ms = 100\n{extra}",
            root.display()
        );
        std::fs::write(&config, text).unwrap();
        Self {
            dir,
            config,
            children: Vec::new(),
        }
    }

    /// Starts `bin` with `--config` and `args`; its logs go to a file
    /// named after `name` in the harness directory.
    pub fn start(&mut self, name: &str, bin: &str, args: &[&str]) {
        let log = std::fs::File::create(self.dir.path().join(format!("{name}.log"))).unwrap();
        let child = Command::new(binary(bin))
            .arg("--config")
            .arg(&self.config)
            .args(args)
            .env("RUST_LOG", "info")
            .stdin(Stdio::null())
            .stdout(log.try_clone().unwrap())
            .stderr(log)
            .spawn()
            .unwrap_or_else(|e| panic!("starting {bin}: {e}"));
        self.children.push((name.to_owned(), child));
    }

    fn index(&self, name: &str) -> usize {
        self.children
            .iter()
            .position(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("no process {name}"))
    }

    pub fn signal(&mut self, name: &str, signal: Signal) {
        let pid = self.children[self.index(name)].1.id();
        kill(Pid::from_raw(pid as i32), signal).unwrap();
    }

    /// Waits for `name` to exit, at most `limit`; removes it.
    pub fn wait(&mut self, name: &str, limit: Duration) -> ExitStatus {
        let index = self.index(name);
        let deadline = Instant::now() + limit;
        loop {
            if let Some(status) = self.children[index].1.try_wait().unwrap() {
                self.children.remove(index);
                return status;
            }
            if Instant::now() > deadline {
                panic!("{name} did not exit within {limit:?}:\n{}", self.log(name));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Whether `name` has not exited.
    pub fn running(&mut self, name: &str) -> bool {
        let index = self.index(name);
        self.children[index].1.try_wait().unwrap().is_none()
    }

    /// SIGKILL, then reap.
    pub fn kill(&mut self, name: &str) {
        self.signal(name, Signal::SIGKILL);
        self.wait(name, Duration::from_secs(5));
    }

    pub fn log(&self, name: &str) -> String {
        std::fs::read_to_string(self.dir.path().join(format!("{name}.log"))).unwrap_or_default()
    }

    pub fn config_arg(&self) -> &str {
        self.config.to_str().unwrap()
    }
}

impl Drop for Harness {
    fn drop(&mut self) {
        for (_, child) in &mut self.children {
            child.kill().ok();
            child.wait().ok();
        }
    }
}

/// Polls `check` every 50 ms until it returns `Some`, at most `limit`.
pub fn eventually<T>(limit: Duration, what: &str, mut check: impl FnMut() -> Option<T>) -> T {
    let deadline = Instant::now() + limit;
    loop {
        if let Some(value) = check() {
            return value;
        }
        assert!(Instant::now() < deadline, "{what}: not within {limit:?}");
        std::thread::sleep(Duration::from_millis(50));
    }
}
