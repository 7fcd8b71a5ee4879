//! The matcher's counters and their periodic publication (off the query
//! path: the WaitSet wakes for it on its own interval).

use std::time::{Duration, Instant};

use vref_reference::{ReferenceState, RejectReason};
use vref_scene::Side;
use vref_wire::ipc::now_ns;
use vref_wire::{AnswerStatus, MAX_ANSWER_STATUSES, MAX_REJECT_REASONS, MatcherStats};

/// How often the statistics are published.
pub const PUBLISH_EVERY: Duration = Duration::from_millis(200);

// Every reason and status must have a slot on the wire.
const _: () = assert!(RejectReason::ALL.len() <= MAX_REJECT_REASONS);
const _: () = assert!(AnswerStatus::ALL.len() <= MAX_ANSWER_STATUSES);

/// What the service counts itself; the state counts rejections and
/// solves.
#[derive(Debug)]
pub struct Counters {
    started: Instant,
    started_ns: u64,
    received: [u64; 2],
    accepted: [u64; 2],
    answers: [u64; MAX_ANSWER_STATUSES],
}

impl Counters {
    pub fn new() -> Self {
        Self {
            started: Instant::now(),
            started_ns: now_ns(),
            received: [0; 2],
            accepted: [0; 2],
            answers: [0; MAX_ANSWER_STATUSES],
        }
    }

    pub fn snapshot(&mut self, side: Side, accepted: bool) {
        self.received[side as usize] += 1;
        self.accepted[side as usize] += u64::from(accepted);
    }

    pub fn answer(&mut self, status: AnswerStatus) {
        self.answers[status as usize] += 1;
    }

    pub fn answered(&self) -> u64 {
        self.answers.iter().sum()
    }

    /// The figures as published.
    pub fn message(&self, state: &ReferenceState) -> MatcherStats {
        let mut rejected = [0; MAX_REJECT_REASONS];
        for reason in RejectReason::ALL {
            rejected[reason as usize] = state.rejections().get(reason);
        }
        MatcherStats {
            started_ns: self.started_ns,
            taken_ns: now_ns(),
            uptime_ms: u64::try_from(self.started.elapsed().as_millis()).unwrap_or(u64::MAX),
            snapshots_received: self.received,
            snapshots_accepted: self.accepted,
            rejected,
            answers: self.answers,
            solves: state.solves(),
            rss_kb: rss_kb().unwrap_or(0),
            pid: std::process::id(),
            ..MatcherStats::default()
        }
    }
}

/// Resident memory of this process (VmRSS in /proc/self/status), kB.
pub fn rss_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_vm_rss(&status)
}

fn parse_vm_rss(status: &str) -> Option<u64> {
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))?
        .trim()
        .strip_suffix("kB")?
        .trim()
        .parse()
        .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vm_rss_is_read_from_the_status_file() {
        let status = "Name:\tvref-matcher\nVmPeak:\t  99 kB\nVmRSS:\t   12345 kB\nThreads:\t1\n";
        assert_eq!(parse_vm_rss(status), Some(12345));
        assert_eq!(parse_vm_rss("VmRSS: lots\n"), None);
        assert_eq!(parse_vm_rss("Name: x\n"), None);
        assert!(rss_kb().is_some_and(|kb| kb > 0));
    }
}
