//! Real service processes for system tests: each harness has its own
//! iceoryx2 root path and prefix, so tests never see each other.
//!
//! Beside `vref_harness::launch` (the launcher of `vref demo`, `soak` and
//! the benchmarks), because tests need what a run does not: any arguments
//! per process, a process's exit status after a signal, SIGKILL of one
//! process, and a watchdog per test. What is the same thing is shared:
//! the binary lookup ([`crate::binary`]) and the readiness wait
//! ([`crate::eventually`]).

use std::path::PathBuf;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex, mpsc};
use std::time::Duration;

use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;

use crate::wait::exit_within;
use crate::watchdog::{Pids, test_limit, watchdog};

/// Processes under test and the files they share.
#[derive(Debug)]
pub struct Harness {
    pub dir: tempfile::TempDir,
    pub config: PathBuf,
    children: Vec<(String, Child)>,
    pids: Pids,
    _watchdog: mpsc::Sender<()>,
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
        let pids = Arc::new(Mutex::new(Vec::new()));
        let watchdog = watchdog(dir.path(), Arc::clone(&pids), test_limit());
        Self {
            dir,
            config,
            children: Vec::new(),
            pids,
            _watchdog: watchdog,
        }
    }

    /// Starts `bin` with `--config` and `args`; its logs go to a file
    /// named after `name` in the harness directory.
    pub fn start(&mut self, name: &str, bin: &str, args: &[&str]) {
        let log = std::fs::File::create(self.dir.path().join(format!("{name}.log"))).unwrap();
        let child = Command::new(crate::binary(bin))
            .arg("--config")
            .arg(&self.config)
            .args(args)
            .env("RUST_LOG", "info")
            .stdin(Stdio::null())
            .stdout(log.try_clone().unwrap())
            .stderr(log)
            .spawn()
            .unwrap_or_else(|e| panic!("starting {bin}: {e}"));
        self.pids
            .lock()
            .unwrap()
            .push((name.to_owned(), child.id()));
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
        let path = self.dir.path().join(format!("{name}.log"));
        let what = || {
            let log = std::fs::read_to_string(&path).unwrap_or_default();
            format!("{name}, whose log is:\n{log}")
        };
        let status = exit_within(&mut self.children[index].1, limit, what);
        let (_, child) = self.children.remove(index);
        self.pids
            .lock()
            .unwrap()
            .retain(|&(_, pid)| pid != child.id());
        status
    }

    /// The process id of `name`.
    pub fn pid(&self, name: &str) -> u32 {
        self.children[self.index(name)].1.id()
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
