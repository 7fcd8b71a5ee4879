//! Capture times: how old a message is, judged on its `timestamp_ns`
//! against this machine's clock, and which stamps are not believable.

use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use crate::{RejectReason, Rejected};

/// One moment on both clocks: the monotonic one for intervals measured
/// here, the wall clock for ages of stamps made elsewhere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Now {
    pub instant: Instant,
    /// Nanoseconds since the Unix epoch.
    pub unix_ns: u64,
}

impl Now {
    pub fn read() -> Self {
        let unix_ns = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX));
        Self {
            instant: Instant::now(),
            unix_ns,
        }
    }

    /// This moment `d` later on both clocks.
    pub fn after(&self, d: Duration) -> Self {
        Self {
            instant: self.instant + d,
            unix_ns: self
                .unix_ns
                .saturating_add(u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)),
        }
    }
}

/// How long ago `timestamp_ns` was at `now`; a stamp from the future (a
/// publisher's clock slightly ahead, within the skew allowed at intake)
/// counts as captured now.
pub fn capture_age(timestamp_ns: u64, now: &Now) -> Duration {
    Duration::from_nanos(now.unix_ns.saturating_sub(timestamp_ns))
}

/// The limits a stamp must keep at intake.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StampLimits {
    pub max_skew: Duration,
    pub max_age: Duration,
}

impl StampLimits {
    /// Refuses a stamp further ahead of `now` than the skew allowed, or
    /// older than any believable capture.
    pub fn check(&self, timestamp_ns: u64, now: &Now) -> Result<(), Rejected> {
        let ahead = Duration::from_nanos(timestamp_ns.saturating_sub(now.unix_ns));
        if ahead > self.max_skew {
            return Err(Rejected {
                reason: RejectReason::TimestampFuture,
                detail: format!(
                    "timestamp is {} ms in the future, more than [matcher] max_clock_skew_ms = {}",
                    ahead.as_millis(),
                    self.max_skew.as_millis()
                ),
            });
        }
        let age = capture_age(timestamp_ns, now);
        if age > self.max_age {
            return Err(Rejected {
                reason: RejectReason::TimestampTooOld,
                detail: format!(
                    "timestamp is {} ms old, more than [matcher] max_capture_age_ms = {}",
                    age.as_millis(),
                    self.max_age.as_millis()
                ),
            });
        }
        Ok(())
    }
}

pub(crate) fn micros(d: Duration) -> u64 {
    u64::try_from(d.as_micros()).unwrap_or(u64::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stamps_ahead_within_the_skew_count_as_now_and_beyond_it_are_refused() {
        let now = Now::read();
        let limits = StampLimits {
            max_skew: Duration::from_millis(100),
            max_age: Duration::from_secs(10),
        };
        let ms = 1_000_000;
        assert_eq!(limits.check(now.unix_ns + 50 * ms, &now), Ok(()));
        assert_eq!(capture_age(now.unix_ns + 50 * ms, &now), Duration::ZERO);
        let ahead = limits.check(now.unix_ns + 5000 * ms, &now).unwrap_err();
        assert_eq!(ahead.reason, RejectReason::TimestampFuture);
        assert!(ahead.detail.contains("5000 ms in the future"), "{ahead}");
        assert_eq!(limits.check(now.unix_ns - 9000 * ms, &now), Ok(()));
        let old = limits
            .check(now.unix_ns - 3_600_000 * ms, &now)
            .unwrap_err();
        assert_eq!(old.reason, RejectReason::TimestampTooOld);
        assert!(old.detail.contains("3600000 ms old"), "{old}");
        assert_eq!(
            capture_age(now.unix_ns - 7 * ms, &now),
            Duration::from_millis(7)
        );
        assert_eq!(
            limits.check(0, &now).unwrap_err().reason,
            RejectReason::TimestampTooOld
        );
    }
}
