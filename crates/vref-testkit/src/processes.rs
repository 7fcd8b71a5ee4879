//! Real service processes for system tests: each harness has its own
//! iceoryx2 root path and prefix, so tests never see each other.
//!
//! The processes are `vref_harness::launch::Services`, the launcher of
//! `vref demo`, `soak` and the benchmarks; a harness adds what tests need
//! and a run does not: any arguments per process, a process's exit status
//! after a signal, SIGKILL of one process, a watchdog per test, and
//! panics instead of errors. The binary lookup ([`crate::binary`]) and the
//! readiness wait ([`crate::eventually`]) are shared too.

use std::path::PathBuf;
use std::process::{Child, Command, ExitStatus};
use std::sync::{Arc, Mutex, mpsc};
use std::time::Duration;

use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;
use vref_harness::launch::Services;

use crate::wait::exit_within;
use crate::watchdog::{Pids, test_limit, watchdog};

/// Processes under test and the files they share.
#[derive(Debug)]
pub struct Harness {
    pub dir: tempfile::TempDir,
    pub config: PathBuf,
    services: Services,
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
        let services = Services::new(dir.path());
        Self {
            dir,
            config,
            services,
            pids,
            _watchdog: watchdog,
        }
    }

    /// Starts `bin` with `--config` and `args`; its logs go to a file
    /// named after `name` in the harness directory.
    pub fn start(&mut self, name: &str, bin: &str, args: &[&str]) {
        let mut command = Command::new(crate::binary(bin));
        command
            .arg("--config")
            .arg(&self.config)
            .args(args)
            .env("RUST_LOG", "info");
        self.services
            .spawn(name, command)
            .unwrap_or_else(|e| panic!("starting {bin}: {e}"));
        let pid = self.pid(name);
        self.pids.lock().unwrap().push((name.to_owned(), pid));
    }

    fn child(&mut self, name: &str) -> &mut Child {
        self.services
            .child(name)
            .unwrap_or_else(|| panic!("no process {name}"))
    }

    pub fn signal(&mut self, name: &str, signal: Signal) {
        let pid = self.child(name).id();
        kill(Pid::from_raw(pid as i32), signal).unwrap();
    }

    /// Waits for `name` to exit, at most `limit`; removes it.
    pub fn wait(&mut self, name: &str, limit: Duration) -> ExitStatus {
        let mut child = self
            .services
            .remove(name)
            .unwrap_or_else(|| panic!("no process {name}"));
        let path = self.dir.path().join(format!("{name}.log"));
        let what = || {
            let log = std::fs::read_to_string(&path).unwrap_or_default();
            format!("{name}, whose log is:\n{log}")
        };
        let status = exit_within(&mut child, limit, what);
        self.pids
            .lock()
            .unwrap()
            .retain(|&(_, pid)| pid != child.id());
        status
    }

    /// The process id of `name`.
    pub fn pid(&self, name: &str) -> u32 {
        self.services
            .pid(name)
            .unwrap_or_else(|| panic!("no process {name}"))
    }

    /// Whether `name` has not exited.
    pub fn running(&mut self, name: &str) -> bool {
        self.child(name).try_wait().unwrap().is_none()
    }

    /// SIGKILL, then reap.
    pub fn kill(&mut self, name: &str) {
        self.signal(name, Signal::SIGKILL);
        self.wait(name, Duration::from_secs(5));
    }

    pub fn log(&self, name: &str) -> String {
        self.services.log(name)
    }

    pub fn config_arg(&self) -> &str {
        self.config.to_str().unwrap()
    }
}

impl Drop for Harness {
    /// A test's processes are killed, not stopped in order: a test that
    /// wanted an orderly stop has signalled and waited for it already.
    fn drop(&mut self) {
        self.services.kill_all();
    }
}
