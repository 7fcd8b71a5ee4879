//! Real service processes for system tests: each harness has its own
//! iceoryx2 root path and prefix, so tests never see each other.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;

pub use vref_testkit::binary;

/// How long one test with a harness may run: 300 s, or
/// `VREF_TEST_LIMIT_SECS`. Every wait in these tests has its own bound,
/// but a call into iceoryx2 or the kernel that never returns has none;
/// past this the test binary is aborted, so that the suite fails, naming
/// the test, instead of stalling until CI gives up.
pub fn test_limit() -> Duration {
    let secs = std::env::var("VREF_TEST_LIMIT_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    Duration::from_secs(secs)
}

/// Processes under test and the files they share.
pub struct Harness {
    pub dir: tempfile::TempDir,
    pub config: PathBuf,
    children: Vec<(String, Child)>,
    pids: Arc<Mutex<Vec<(String, u32)>>>,
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
        let deadline = Instant::now() + limit;
        loop {
            if let Some(status) = self.children[index].1.try_wait().unwrap() {
                let (_, child) = self.children.remove(index);
                self.pids
                    .lock()
                    .unwrap()
                    .retain(|&(_, pid)| pid != child.id());
                return status;
            }
            if Instant::now() > deadline {
                panic!("{name} did not exit within {limit:?}:\n{}", self.log(name));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
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

/// Past `limit` with the harness still alive (the returned sender not
/// dropped): says which test hung on stderr (uncaptured, since the test's
/// captured output dies with the process), with its services' last log
/// lines, kills the services and aborts the test binary.
fn watchdog(dir: &Path, pids: Arc<Mutex<Vec<(String, u32)>>>, limit: Duration) -> mpsc::Sender<()> {
    let (alive, until_dropped) = mpsc::channel::<()>();
    let test = std::thread::current().name().unwrap_or("a test").to_owned();
    let dir = dir.to_owned();
    std::thread::spawn(move || {
        if until_dropped.recv_timeout(limit) != Err(RecvTimeoutError::Timeout) {
            return;
        }
        let mut report = format!(
            "\n{test}: still running after {limit:?}; its services are killed and the test binary aborted\n"
        );
        report += &backtraces();
        for (name, pid) in pids.lock().map(|p| p.clone()).unwrap_or_default() {
            kill(Pid::from_raw(pid as i32), Signal::SIGKILL).ok();
            report += &format!("killed {name} (pid {pid})\n");
        }
        let mut logs: Vec<_> = std::fs::read_dir(&dir)
            .into_iter()
            .flatten()
            .flatten()
            .map(|entry| entry.path())
            .filter(|path| path.extension().is_some_and(|e| e == "log"))
            .collect();
        logs.sort();
        for log in logs {
            let text = std::fs::read_to_string(&log).unwrap_or_default();
            let lines: Vec<&str> = text.lines().collect();
            let tail = lines[lines.len().saturating_sub(20)..].join("\n");
            report += &format!("--- last lines of {}:\n{tail}\n", log.display());
        }
        std::io::stderr().write_all(report.as_bytes()).ok();
        std::process::abort();
    });
    alive
}

/// Every thread's stack of this process, by gdb if the machine has it:
/// where a hung test waits is what a report of it needs most.
fn backtraces() -> String {
    let pid = std::process::id().to_string();
    let gdb = Command::new("gdb")
        .args(["-p", &pid, "-batch", "-ex", "thread apply all bt"])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn();
    let Ok(gdb) = gdb else {
        return "(no gdb on this machine: no backtraces)\n".to_owned();
    };
    let id = gdb.id();
    let reader = std::thread::spawn(move || gdb.wait_with_output());
    let deadline = Instant::now() + Duration::from_secs(60);
    while !reader.is_finished() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(50));
    }
    if !reader.is_finished() {
        kill(Pid::from_raw(id as i32), Signal::SIGKILL).ok();
    }
    match reader.join() {
        Ok(Ok(output)) => format!(
            "--- backtraces:\n{}\n",
            String::from_utf8_lossy(&output.stdout)
        ),
        _ => "(gdb failed: no backtraces)\n".to_owned(),
    }
}

/// Waits for `thread` to finish, at most `limit`, and returns its result;
/// a thread that waits on another process must not hang its test.
pub fn join_within<T>(thread: std::thread::JoinHandle<T>, limit: Duration, what: &str) -> T {
    eventually(limit, what, || thread.is_finished().then_some(()));
    thread.join().unwrap()
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
