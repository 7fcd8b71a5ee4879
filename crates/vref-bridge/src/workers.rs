//! The bridge's threads by name: watched while it runs (one that ends
//! early stops the bridge) and joined when it stops.

use std::thread::JoinHandle;

use crate::BridgeError;

/// A thread of the bridge; it ends with the reason it stopped.
pub(crate) type Worker = JoinHandle<Result<(), BridgeError>>;

#[derive(Debug, Default)]
pub(crate) struct Workers(Vec<(&'static str, Worker)>);

impl Workers {
    pub fn push(&mut self, name: &'static str, worker: Worker) {
        self.0.push((name, worker));
    }

    /// The first thread that has ended: every thread runs until asked
    /// to stop, so one that ended on its own failed.
    pub fn ended(&self) -> Option<BridgeError> {
        self.0
            .iter()
            .find(|(_, worker)| worker.is_finished())
            .map(|&(name, _)| BridgeError::Stopped { name })
    }

    /// Waits for every thread; the first failure, in the order the
    /// threads were started. Every thread's error is logged, as only the
    /// first is returned.
    pub fn join(self) -> Option<BridgeError> {
        let mut first = None;
        for (name, worker) in self.0 {
            let failure = match worker.join() {
                Ok(Ok(())) => continue,
                Ok(Err(e)) => {
                    let e = BridgeError::Thread {
                        name,
                        source: Box::new(e),
                    };
                    tracing::error!("{}", vref_logging::with_causes(&e));
                    e
                }
                Err(_) => BridgeError::Panicked { name },
            };
            first.get_or_insert(failure);
        }
        first
    }
}

#[cfg(test)]
mod tests {
    use std::time::{Duration, Instant};

    use super::*;
    use crate::NetError;

    fn failing() -> Result<(), BridgeError> {
        Err(BridgeError::Net(NetError::Zenoh {
            what: "receiving queries".to_owned(),
            message: "closed".to_owned(),
        }))
    }

    /// Waits up to a few seconds for `done`.
    fn within_seconds(done: impl Fn() -> bool) -> bool {
        let deadline = Instant::now() + Duration::from_secs(10);
        while Instant::now() < deadline {
            if done() {
                return true;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        false
    }

    #[test]
    fn a_thread_that_ends_is_named() {
        let (tx, rx) = std::sync::mpsc::channel::<()>();
        let mut workers = Workers::default();
        workers.push(
            "waiting",
            std::thread::spawn(move || {
                rx.recv_timeout(Duration::from_secs(10)).ok();
                Ok(())
            }),
        );
        workers.push("quitting", std::thread::spawn(|| Ok(())));
        assert!(within_seconds(|| workers.ended().is_some()));
        assert!(matches!(
            workers.ended(),
            Some(BridgeError::Stopped { name: "quitting" })
        ));
        tx.send(()).ok();
        assert!(workers.join().is_none());
    }

    #[test]
    fn joining_gives_the_first_failure_in_starting_order() {
        let mut workers = Workers::default();
        workers.push("fine", std::thread::spawn(|| Ok(())));
        workers.push(
            "panicking",
            std::thread::spawn(|| panic!("a thread of the test panics on purpose")),
        );
        workers.push("failing", std::thread::spawn(failing));
        let first = workers.join();
        assert!(
            matches!(first, Some(BridgeError::Panicked { name: "panicking" })),
            "{first:?}"
        );

        let mut workers = Workers::default();
        workers.push("failing", std::thread::spawn(failing));
        let Some(e) = workers.join() else {
            panic!("no failure");
        };
        assert_eq!(
            vref_logging::with_causes(&e),
            "the failing thread: receiving queries: closed",
            "{e:?}"
        );
    }
}
