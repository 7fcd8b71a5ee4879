//! Bounded waits for tests, on the product's one readiness wait
//! (`vref_harness::ready::wait_ready`): a test that waits for something
//! that never comes fails, naming it, instead of hanging.

use std::process::{Child, ExitStatus};
use std::thread::JoinHandle;
use std::time::Duration;

use vref_harness::ready::{Readiness, wait_ready};

/// How often a test's wait looks again.
const EVERY: Duration = Duration::from_millis(50);

/// Polls `check` until it returns `Some`, at most `limit`; panics naming
/// `what` past it.
pub fn eventually<T>(limit: Duration, what: &str, mut check: impl FnMut() -> Option<T>) -> T {
    let waited = wait_ready(limit, EVERY, || {
        Ok(match check() {
            Some(value) => Readiness::Ready(value),
            None => Readiness::Waiting(what.to_owned()),
        })
    });
    waited.unwrap_or_else(|e| panic!("{e}"))
}

/// Waits for `thread` to finish, at most `limit`, and returns its result;
/// a thread that waits on another process must not hang its test.
pub fn join_within<T>(thread: JoinHandle<T>, limit: Duration, what: &str) -> T {
    eventually(limit, what, || thread.is_finished().then_some(()));
    thread
        .join()
        .unwrap_or_else(|panicked| std::panic::resume_unwind(panicked))
}

/// Waits for `child` to exit, at most `limit`; past it the child is
/// killed and the test fails, naming it with `what()`.
pub fn exit_within(child: &mut Child, limit: Duration, what: impl Fn() -> String) -> ExitStatus {
    let waited = wait_ready(limit, Duration::from_millis(10), || {
        Ok(match child.try_wait().unwrap() {
            Some(status) => Readiness::Ready(status),
            None => Readiness::Waiting("exit".to_owned()),
        })
    });
    waited.unwrap_or_else(|_| {
        child.kill().ok();
        child.wait().ok();
        panic!("{} did not exit within {limit:?}", what())
    })
}
