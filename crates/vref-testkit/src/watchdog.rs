//! The suite's guard against a hang: every wait in the tests has its own
//! bound, but a call into iceoryx2 or the kernel that never returns has
//! none. Past [`test_limit`] the test binary is aborted, so that the suite
//! fails, naming the test, instead of stalling until CI gives up.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;

/// The processes a harness runs, by name, for the watchdog to kill.
pub type Pids = Arc<Mutex<Vec<(String, u32)>>>;

/// How long one test with a harness may run: 300 s, or
/// `VREF_TEST_LIMIT_SECS`; a hang guard, not a measurement.
pub fn test_limit() -> Duration {
    let secs = std::env::var("VREF_TEST_LIMIT_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    Duration::from_secs(secs)
}

/// Past `limit` with the harness still alive (the returned sender not
/// dropped): says which test hung on stderr (uncaptured, since the test's
/// captured output dies with the process), with its services' last log
/// lines, kills the services and aborts the test binary.
pub fn watchdog(dir: &Path, pids: Pids, limit: Duration) -> mpsc::Sender<()> {
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
