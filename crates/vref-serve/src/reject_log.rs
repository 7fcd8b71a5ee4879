//! Rejection logs that one publisher cannot flood: the first rejection of
//! each (service, reason, publisher port) in an interval is logged with
//! its detail, the others of that interval as one count at its end.

use std::time::{Duration, Instant};

use vref_reference::RejectReason;

/// Distinct (service, reason, port) kept per interval; more fall into one
/// count without a port.
const KEYS: usize = 64;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Key {
    service: &'static str,
    reason: RejectReason,
    origin: u128,
}

/// Rejections not logged one by one, for the interval's summary line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Suppressed {
    pub service: &'static str,
    pub reason: RejectReason,
    pub count: u64,
}

#[derive(Debug)]
pub struct RejectLog {
    interval: Duration,
    started: Instant,
    seen: Vec<(Key, u64)>,
    overflow: u64,
}

impl RejectLog {
    pub fn new(interval: Duration, now: Instant) -> Self {
        Self {
            interval,
            started: now,
            seen: Vec::with_capacity(KEYS),
            overflow: 0,
        }
    }

    /// Whether this rejection is the first of its key in the interval and
    /// should be logged in full; otherwise it is counted for the summary.
    pub fn note(&mut self, service: &'static str, reason: RejectReason, origin: u128) -> bool {
        let key = Key {
            service,
            reason,
            origin,
        };
        if let Some((_, count)) = self.seen.iter_mut().find(|(k, _)| *k == key) {
            *count += 1;
            return false;
        }
        if self.seen.len() < KEYS {
            self.seen.push((key, 0));
            return true;
        }
        self.overflow += 1;
        false
    }

    /// At the end of an interval: what was not logged one by one, summed
    /// over ports, and a new interval begins; `None` before its end.
    pub fn flush(&mut self, now: Instant) -> Option<(Vec<Suppressed>, u64)> {
        if now.saturating_duration_since(self.started) < self.interval {
            return None;
        }
        self.started = now;
        let mut summary: Vec<Suppressed> = Vec::new();
        for (key, count) in self.seen.drain(..).filter(|(_, n)| *n > 0) {
            match summary
                .iter_mut()
                .find(|s| s.service == key.service && s.reason == key.reason)
            {
                Some(s) => s.count += count,
                None => summary.push(Suppressed {
                    service: key.service,
                    reason: key.reason,
                    count,
                }),
            }
        }
        let overflow = std::mem::take(&mut self.overflow);
        Some((summary, overflow))
    }

    pub fn interval(&self) -> Duration {
        self.interval
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_of_each_key_is_logged_and_the_rest_summed_per_interval() {
        let t = Instant::now();
        let mut log = RejectLog::new(Duration::from_secs(10), t);
        let backwards = RejectReason::SequenceBackwards;
        assert!(log.note("robot snapshot", backwards, 1));
        for _ in 0..1000 {
            assert!(!log.note("robot snapshot", backwards, 1));
        }
        // Another publisher, or another reason, is logged on its own.
        assert!(log.note("robot snapshot", backwards, 2));
        assert!(log.note("robot snapshot", RejectReason::NonFinitePosition, 1));
        assert!(log.note("ray", backwards, 1));
        assert_eq!(log.flush(t + Duration::from_secs(1)), None);
        let (summary, overflow) = log.flush(t + Duration::from_secs(10)).unwrap_or_default();
        assert_eq!(
            summary,
            vec![Suppressed {
                service: "robot snapshot",
                reason: backwards,
                count: 1000
            }]
        );
        assert_eq!(overflow, 0);
        assert!(log.note("robot snapshot", backwards, 1), "a new interval");
    }
}
