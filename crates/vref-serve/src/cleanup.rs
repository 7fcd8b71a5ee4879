//! Dead-node cleanup on a thread of its own. iceoryx2 finds dead nodes by
//! listing every node of the root path and reading its files, which takes
//! milliseconds each round: on the WaitSet thread a query arriving then
//! waited for it.

use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use vref_wire::ipc::{IpcSettings, create_node};

use crate::ServeError;

/// The cleanup thread; [`CleanupThread::stop`] ends it.
#[derive(Debug)]
pub struct CleanupThread {
    stop: Arc<Stop>,
    thread: Option<JoinHandle<()>>,
}

/// Set once, on shutdown; the thread sleeps on it between rounds.
#[derive(Debug, Default)]
struct Stop {
    stopped: Mutex<bool>,
    wake: Condvar,
}

impl Stop {
    fn set(&self) {
        *self.stopped.lock().unwrap_or_else(PoisonError::into_inner) = true;
        self.wake.notify_all();
    }

    /// Sleeps `every` or until stopped; whether it was stopped.
    fn wait(&self, every: Duration) -> bool {
        let stopped = self.stopped.lock().unwrap_or_else(PoisonError::into_inner);
        let (stopped, _) = self
            .wake
            .wait_timeout_while(stopped, every, |stopped| !*stopped)
            .unwrap_or_else(PoisonError::into_inner);
        *stopped
    }
}

impl CleanupThread {
    /// Cleans up every `every` with a node of its own, at nice `nice`.
    pub fn spawn(ipc: IpcSettings, every: Duration, nice: i32) -> Result<Self, ServeError> {
        let stop = Arc::new(Stop::default());
        let shared = Arc::clone(&stop);
        let thread = std::thread::Builder::new()
            .name("cleanup".to_owned())
            .spawn(move || clean_until_stopped(&ipc, every, nice, &shared))
            .map_err(ServeError::Thread)?;
        Ok(Self {
            stop,
            thread: Some(thread),
        })
    }

    /// Stops the thread and waits for the round in progress.
    pub fn stop(mut self) {
        self.stop.set();
        if let Some(thread) = self.thread.take()
            && thread.join().is_err()
        {
            tracing::error!("the cleanup thread panicked");
        }
    }
}

fn clean_until_stopped(ipc: &IpcSettings, every: Duration, nice: i32, stop: &Stop) {
    if let Err(e) = crate::priority::set_this_thread_nice(nice) {
        tracing::warn!(nice, "the cleanup thread keeps its priority: {e}");
    }
    // Its own node: iceoryx2's nodes belong to the thread that made them.
    let node = match create_node(ipc, "vref-matcher-cleanup") {
        Ok(node) => node,
        Err(e) => {
            tracing::error!("dead nodes will not be cleaned up: {e}");
            return;
        }
    };
    loop {
        let started = Instant::now();
        let cleanup = node.try_cleanup_dead_nodes();
        if cleanup.cleanups > 0 || cleanup.failed_cleanups > 0 {
            tracing::info!(
                cleaned = cleanup.cleanups,
                failed = cleanup.failed_cleanups,
                took_us = started.elapsed().as_micros(),
                "dead nodes"
            );
        }
        if stop.wait(every) {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stop_wakes_the_sleeper_at_once() {
        let stop = Arc::new(Stop::default());
        let shared = Arc::clone(&stop);
        let sleeper = std::thread::spawn(move || {
            let started = Instant::now();
            (shared.wait(Duration::from_secs(60)), started.elapsed())
        });
        std::thread::sleep(Duration::from_millis(50));
        stop.set();
        let (stopped, slept) = sleeper.join().unwrap_or((false, Duration::MAX));
        assert!(stopped);
        assert!(slept < Duration::from_secs(30), "{slept:?}");
    }

    #[test]
    fn without_a_stop_the_sleep_runs_out() {
        assert!(!Stop::default().wait(Duration::from_millis(20)));
    }
}
