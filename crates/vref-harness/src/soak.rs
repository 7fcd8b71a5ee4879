//! `vref soak`: the three services under load for a long time. Both feeds
//! publish at a high rate, queries go at a fixed rate, and the matcher's
//! own statistics (snapshots received, rejections, resident memory) are
//! read from its stats service. [`run`] returns the [`Report`].

use std::collections::BTreeMap;
use std::path::Path;
use std::time::{Duration, Instant};

use vref_config::Config;
use vref_feed::synthetic_world;
use vref_reference::RejectReason;
use vref_scene::Side;
use vref_sim::LiveWorld;
use vref_wire::ipc::{IpcError, ReferenceClient, StatsReader, now_ns};
use vref_wire::{AnswerStatus, MatcherStats};

use crate::Finished;
use crate::demo::ask;
use crate::launch::{Services, prepare};
use crate::ready::{READY_WITHIN, Readiness, ReadyError, wait_ready};
use crate::{RunError, now_s};

/// How long to wait for statistics taken after a given moment (the
/// matcher publishes every 200 ms).
const STATS_WITHIN: Duration = Duration::from_secs(5);
/// How often the children are checked for having died.
const CHECK_EVERY: Duration = Duration::from_millis(500);

/// What `vref soak` was asked.
#[derive(Debug, Clone)]
pub struct SoakOptions {
    /// How long to send queries after warm-up.
    pub duration: Duration,
    /// Objects in the synthetic world (default: the preset's draw).
    pub objects: Option<usize>,
    /// Snapshots per second of each feed.
    pub feed_rate: f64,
    /// Queries per second, one at a time.
    pub query_rate: f64,
    /// One query's time limit.
    pub timeout: Duration,
}

/// Runs the soak: the services from `bin_dir` under `config` isolated,
/// the feeds at `options.feed_rate`, queries at `options.query_rate`.
pub fn run(
    options: &SoakOptions,
    config: &Config,
    bin_dir: &Path,
) -> Result<Finished<Report>, RunError> {
    // The world the feeds publish, computed here too: queries point where
    // the person points.
    let (_, world) = synthetic_world(&config.feeds, options.objects)?;
    let mut feed_args = vec!["--rate".to_owned(), options.feed_rate.to_string()];
    if let Some(n) = options.objects {
        feed_args.extend(["--objects".to_owned(), n.to_string()]);
    }
    prepare(config, bin_dir, "soak", "vsoak")?.run_system(
        &feed_args,
        |run, services| soak(options, run.config, &world, services),
        // The feeds log what they published as they stop.
        |report, services| {
            report.published = [
                published_snapshots(&services.log("vref-perception-feed")),
                published_snapshots(&services.log("vref-gesture-feed")),
            ];
        },
    )
}

/// What one soak run saw.
#[derive(Debug, Default)]
pub struct Report {
    duration_s: f64,
    feed_rate: f64,
    query_rate: f64,
    queries: u64,
    answered: u64,
    timeouts: u64,
    /// Client failures other than a timeout.
    ipc_errors: u64,
    by_status: [u64; AnswerStatus::ALL.len()],
    rtt_us: Vec<u64>,
    /// Snapshots the feeds say they published, robot then human (from
    /// their logs at exit; `None` if the line was not found).
    published: [Option<u64>; 2],
    start: MatcherStats,
    end: MatcherStats,
}

fn soak(
    args: &SoakOptions,
    config: &Config,
    world: &LiveWorld,
    services: &mut Services,
) -> Result<Report, RunError> {
    let name = format!("vref-soak-{}", std::process::id());
    let mut client = ReferenceClient::connect(&config.ipc, &name)?;
    let stats = StatsReader::connect(&config.ipc, &format!("{name}-stats"))?;
    let timeout = args.timeout;

    warm_up(&mut client, &stats, world, services)?;
    // Memory at start is taken once the matcher has answered and solved:
    // its buffers exist, so growth from here on is what a leak looks like.
    let start = stats_after(&stats, now_ns(), services)?;

    let mut report = Report {
        feed_rate: args.feed_rate,
        query_rate: args.query_rate,
        start,
        ..Report::default()
    };
    let period = Duration::from_secs_f64(1.0 / args.query_rate);
    let began = Instant::now();
    let end = began + args.duration;
    let mut next = began;
    let mut next_check = began + CHECK_EVERY;
    while Instant::now() < end {
        let asked = Instant::now();
        let result = match world.gesture(now_s()) {
            Some(gesture) => ask(&mut client, &gesture, timeout),
            None => client.latest_gesture(timeout),
        };
        report.queries += 1;
        match result {
            Ok(answer) => {
                report.answered += 1;
                report.by_status[answer.status() as usize] += 1;
                report
                    .rtt_us
                    .push(u64::try_from(asked.elapsed().as_micros()).unwrap_or(u64::MAX));
            }
            Err(IpcError::Timeout { .. } | IpcError::NoServer { .. }) => report.timeouts += 1,
            Err(e) => {
                report.ipc_errors += 1;
                tracing::warn!("query failed: {e}");
            }
        }
        let now = Instant::now();
        if now >= next_check {
            next_check = now + CHECK_EVERY;
            check_alive(services)?;
        }
        // A fixed schedule; after a stall it resumes at the rate instead
        // of catching up in a burst.
        next += period;
        if next < now {
            next = now;
        }
        if let Some(rest) = next.checked_duration_since(Instant::now()) {
            std::thread::sleep(rest);
        }
    }
    report.duration_s = began.elapsed().as_secs_f64();
    report.end = stats_after(&stats, now_ns(), services)?;
    Ok(report)
}

/// Waits for a first useful answer and a first solve.
fn warm_up(
    client: &mut ReferenceClient,
    stats: &StatsReader,
    world: &LiveWorld,
    services: &mut Services,
) -> Result<(), RunError> {
    let mut answered = false;
    let mut solved = false;
    wait_ready(READY_WITHIN, Duration::from_millis(50), || {
        services.ensure_running()?;
        if !answered {
            let result = match world.gesture(now_s()) {
                Some(g) => ask(client, &g, Duration::from_millis(500)),
                None => client.latest_gesture(Duration::from_millis(500)),
            };
            answered = result
                .is_ok_and(|a| !matches!(a.status(), AnswerStatus::NotReady | AnswerStatus::Stale));
        }
        if let Some(s) = stats.latest()? {
            solved |= s.solves > 0;
        }
        Ok(if answered && solved {
            Readiness::Ready(())
        } else {
            Readiness::Waiting("answer and no solve from the services".to_owned())
        })
    })
    .map_err(soak_error)
}

/// The first statistics taken at or after `after_ns`.
fn stats_after(
    stats: &StatsReader,
    after_ns: u64,
    services: &mut Services,
) -> Result<MatcherStats, RunError> {
    wait_ready(STATS_WITHIN, Duration::from_millis(20), || {
        if let Some(s) = stats.latest()?
            && s.taken_ns >= after_ns
        {
            return Ok(Readiness::Ready(s));
        }
        services.ensure_running()?;
        Ok(Readiness::Waiting("statistics".to_owned()))
    })
    .map_err(|e| match e {
        ReadyError::Timeout { .. } => RunError::NoStats(STATS_WITHIN),
        other => soak_error(other),
    })
}

/// A wait's error as the soak reports it: a death is the soak's, as it is
/// once measuring, and an IPC failure is the run's own.
fn soak_error(error: ReadyError) -> RunError {
    match error {
        ReadyError::Died(source) => died(source),
        ReadyError::Ipc(e) => RunError::Ipc(e),
        other => other.into(),
    }
}

fn died(source: crate::launch::LaunchError) -> RunError {
    RunError::Died {
        run: "soak",
        source,
    }
}

fn check_alive(services: &mut Services) -> Result<(), RunError> {
    services.ensure_running().map_err(died)
}

/// The `snapshots=N` of a feed's last "stopped" log line.
fn published_snapshots(log: &str) -> Option<u64> {
    log.lines()
        .rev()
        .find(|l| l.contains("stopped"))?
        .split_whitespace()
        .find_map(|w| w.strip_prefix("snapshots="))?
        .parse()
        .ok()
}

/// `q` in 0..=1 of sorted values (nearest rank, vref_measure's one
/// definition); 0 if there are none.
fn percentile(sorted: &[u64], q: f64) -> u64 {
    vref_measure::percentile(sorted, q).unwrap_or(0)
}

/// Answers that did not give a usable reference: by status, plus client
/// failures other than a timeout.
const ERROR_STATUSES: [AnswerStatus; 3] = [
    AnswerStatus::NotReady,
    AnswerStatus::Stale,
    AnswerStatus::BadRequest,
];

impl Report {
    fn rtt(&self) -> [u64; 4] {
        let mut sorted = self.rtt_us.clone();
        sorted.sort_unstable();
        [
            percentile(&sorted, 0.5),
            percentile(&sorted, 0.99),
            percentile(&sorted, 0.999),
            sorted.last().copied().unwrap_or(0),
        ]
    }

    fn errors(&self) -> BTreeMap<&'static str, u64> {
        let mut errors: BTreeMap<_, _> = ERROR_STATUSES
            .iter()
            .map(|s| (s.name(), self.by_status[*s as usize]))
            .collect();
        errors.insert("ipc", self.ipc_errors);
        errors
    }

    fn statuses(&self) -> BTreeMap<&'static str, u64> {
        AnswerStatus::ALL
            .iter()
            .map(|s| (s.name(), self.by_status[*s as usize]))
            .collect()
    }

    /// Rejections during the whole run, warm-up included.
    fn rejected(&self) -> BTreeMap<&'static str, u64> {
        RejectReason::ALL
            .iter()
            .map(|r| (r.name(), self.end.rejected[*r as usize]))
            .collect()
    }

    fn rss_growth_kb(&self) -> i64 {
        i64::try_from(self.end.rss_kb).unwrap_or(i64::MAX)
            - i64::try_from(self.start.rss_kb).unwrap_or(i64::MAX)
    }

    /// The `--json` line (without its newline).
    pub fn json(&self) -> String {
        let [p50, p99, p999, max] = self.rtt();
        let side = |v: [u64; 2]| serde_json::json!({"robot": v[0], "human": v[1]});
        serde_json::json!({
            "duration_s": self.duration_s,
            "feed_rate_hz": self.feed_rate,
            "query_rate_hz": self.query_rate,
            "queries": self.queries,
            "answered": self.answered,
            "unanswered": self.queries - self.answered,
            "timeouts": self.timeouts,
            "errors": self.errors(),
            "statuses": self.statuses(),
            "rejected": self.rejected(),
            "snapshots": {
                "published": {"robot": self.published[0], "human": self.published[1]},
                "received": side(self.end.snapshots_received),
                "accepted": side(self.end.snapshots_accepted),
            },
            "solves": self.end.solves,
            "rtt_p50_us": p50,
            "rtt_p99_us": p99,
            "rtt_p999_us": p999,
            "rtt_max_us": max,
            "rss_start_kb": self.start.rss_kb,
            "rss_end_kb": self.end.rss_kb,
            "rss_growth_kb": self.rss_growth_kb(),
        })
        .to_string()
    }

    /// The report a person reads.
    pub fn table(&self) -> String {
        let [p50, p99, p999, max] = self.rtt();
        let count = |m: BTreeMap<&str, u64>| {
            let parts: Vec<String> = m
                .into_iter()
                .filter(|(_, n)| *n > 0)
                .map(|(k, n)| format!("{k} {n}"))
                .collect();
            if parts.is_empty() {
                "none".to_owned()
            } else {
                parts.join(", ")
            }
        };
        let published = |v: Option<u64>| v.map_or_else(|| "?".to_owned(), |n| n.to_string());
        let (r, h) = (Side::Robot as usize, Side::Human as usize);
        format!(
            "soak of {:.1} s, feeds at {} Hz, queries at {} Hz\n\
             snapshots: robot published {} received {} accepted {}; \
             human published {} received {} accepted {}\n\
             rejected: {}\n\
             queries {}, answered {}, timeouts {}, other failures {}\n\
             statuses: {}\n\
             round trip: p50 {p50} us, p99 {p99} us, p99.9 {p999} us, max {max} us\n\
             solves {}; matcher resident memory {} kB after warm-up, {} kB at the end ({:+} kB)\n",
            self.duration_s,
            self.feed_rate,
            self.query_rate,
            published(self.published[r]),
            self.end.snapshots_received[r],
            self.end.snapshots_accepted[r],
            published(self.published[h]),
            self.end.snapshots_received[h],
            self.end.snapshots_accepted[h],
            count(self.rejected()),
            self.queries,
            self.answered,
            self.timeouts,
            self.ipc_errors,
            count(self.statuses()),
            self.end.solves,
            self.start.rss_kb,
            self.end.rss_kb,
            self.rss_growth_kb(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn published_count_is_read_from_the_last_stopped_line() {
        let log = "INFO vref-perception-feed publishing rate_hz=Some(100.0)\n\
                   INFO snapshots=5 gestures=0 vref-perception-feed stopped\n\
                   INFO snapshots=1234 gestures=7 vref-perception-feed stopped\n";
        assert_eq!(published_snapshots(log), Some(1234));
        assert_eq!(published_snapshots("INFO publishing\n"), None);
    }

    #[test]
    fn percentiles_by_nearest_rank() {
        let sorted: Vec<u64> = (1..=1000).collect();
        assert_eq!(percentile(&sorted, 0.5), 500);
        assert_eq!(percentile(&sorted, 0.99), 990);
        assert_eq!(percentile(&sorted, 0.999), 999);
        assert_eq!(percentile(&[], 0.5), 0);
    }
}
