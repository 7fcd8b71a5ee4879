//! The one readiness wait: poll a check until it says ready, at most for
//! a bound. Every command that waits for services (demo, soak, the
//! benchmarks) waits through [`wait_ready`], with its own check.

use std::time::{Duration, Instant};

use crate::launch::LaunchError;

/// How long freshly started services may take to be ready (a first
/// answer, a first solve): generous for a cold start on a busy 2-core
/// machine, so that a timeout means something is wrong.
pub const READY_WITHIN: Duration = Duration::from_secs(30);

/// What a check found.
#[derive(Debug)]
pub enum Readiness<T> {
    /// Ready, with what the check learnt.
    Ready(T),
    /// Not yet; what is still awaited, in words (the timeout names it).
    Waiting(String),
}

/// Why the wait ended without readiness.
#[derive(Debug, thiserror::Error)]
pub enum ReadyError {
    #[error("no {waiting} within {within:?}")]
    Timeout { within: Duration, waiting: String },
    /// A service exited while it was awaited.
    #[error(transparent)]
    Died(#[from] LaunchError),
    #[error(transparent)]
    Ipc(#[from] vref_wire::ipc::IpcError),
}

/// Runs `check` every `every` until it returns [`Readiness::Ready`] (its
/// value returned), an error (returned at once), or `within` has passed
/// ([`ReadyError::Timeout`] naming what the last check still awaited).
pub fn wait_ready<T>(
    within: Duration,
    every: Duration,
    mut check: impl FnMut() -> Result<Readiness<T>, ReadyError>,
) -> Result<T, ReadyError> {
    let deadline = Instant::now() + within;
    loop {
        let waiting = match check()? {
            Readiness::Ready(value) => return Ok(value),
            Readiness::Waiting(what) => what,
        };
        if Instant::now() >= deadline {
            return Err(ReadyError::Timeout { within, waiting });
        }
        std::thread::sleep(every);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ready_returns_the_checks_value_and_a_timeout_names_what_was_awaited() {
        let mut n = 0;
        let got = wait_ready(Duration::from_secs(5), Duration::from_millis(1), || {
            n += 1;
            Ok(if n < 3 {
                Readiness::Waiting("x".to_owned())
            } else {
                Readiness::Ready(n)
            })
        });
        assert!(matches!(got, Ok(3)));
        let late: Result<(), _> =
            wait_ready(Duration::from_millis(20), Duration::from_millis(5), || {
                Ok(Readiness::Waiting("answer from the echo server".to_owned()))
            });
        assert!(late.is_err_and(|e| e.to_string() == "no answer from the echo server within 20ms"));
        let failed: Result<(), _> =
            wait_ready(Duration::from_secs(5), Duration::from_millis(1), || {
                Err(ReadyError::Died(LaunchError::NoService(
                    "broken".to_owned(),
                )))
            });
        assert!(failed.is_err_and(|e| e.to_string() == "no service broken"));
    }
}
