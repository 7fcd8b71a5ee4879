//! `vref bench client`: a Rust [`ReferenceClient`] querying a matcher that
//! is already running, one latest-gesture query at a time, with round-trip
//! percentiles of answers from a solution an earlier answer came from
//! ("cached") and of the first answer from each new solution (as `vref
//! bench query` counts them; the matcher never solves on the query path).
//! `python -m vref_client.bench` runs it beside the Python client against
//! the same matcher, so both are measured under the same load.

use std::time::{Duration, Instant};

use vref_wire::AnswerStatus;
use vref_wire::ipc::{IpcError, IpcSettings, ReferenceClient};

use crate::RunError;
use crate::ready::{self, Readiness};
use crate::samples::{Samples, us};
use crate::table::Table;

/// One query's time limit.
const QUERY_TIMEOUT: Duration = Duration::from_secs(2);

/// What `vref bench client` was asked for.
#[derive(Debug, Clone)]
pub struct ClientBenchOptions {
    /// Queries per second, one at a time.
    pub rate: f64,
    pub duration: Duration,
    /// How long to wait for a first ok or ambiguous answer.
    pub ready_within: Duration,
}

/// What one run measured.
#[derive(Debug, Default)]
pub struct Report {
    cached: Samples,
    solve: Samples,
    /// Answers that did not come from a solution (not ready, stale, no
    /// object in the ray's cone, ...).
    other: u64,
    timeouts: u64,
    errors: u64,
    /// The (robot, human) sequences of the last answer's solution.
    last_solution: Option<(u64, u64)>,
}

/// Connects to the matcher under `ipc`, waits for it to answer, measures.
pub fn run(options: &ClientBenchOptions, ipc: &IpcSettings) -> Result<Report, RunError> {
    let name = format!("vref-bench-client-{}", std::process::id());
    let mut client = ReferenceClient::connect(ipc, &name)?;
    wait_ready(&mut client, options.ready_within)?;
    Ok(measure(&mut client, options))
}

fn wait_ready(client: &mut ReferenceClient, within: Duration) -> Result<(), RunError> {
    ready::wait_ready(within, Duration::from_millis(100), || {
        let ready = client
            .latest_gesture(QUERY_TIMEOUT)
            .is_ok_and(|a| matches!(a.status(), AnswerStatus::Ok | AnswerStatus::Ambiguous));
        Ok(if ready {
            Readiness::Ready(())
        } else {
            Readiness::Waiting("ok or ambiguous latest-gesture answer".to_owned())
        })
    })
    .map_err(|e| RunError::NotServing(Box::new(e)))
}

fn measure(client: &mut ReferenceClient, options: &ClientBenchOptions) -> Report {
    let mut report = Report::default();
    let period = Duration::from_secs_f64(1.0 / options.rate);
    let end = Instant::now() + options.duration;
    while Instant::now() < end {
        let started = Instant::now();
        let result = client.latest_gesture(QUERY_TIMEOUT);
        let took = started.elapsed();
        match result {
            // Only these went through the solution; the snapshots it names
            // tell a solution new since the last answer.
            Ok(a) if matches!(a.status(), AnswerStatus::Ok | AnswerStatus::Ambiguous) => {
                let solution = (a.robot_sequence, a.human_sequence);
                let new = report.last_solution.is_some_and(|last| last != solution);
                report.last_solution = Some(solution);
                if new {
                    report.solve.push(took);
                } else {
                    report.cached.push(took);
                }
            }
            Ok(_) => report.other += 1,
            Err(IpcError::Timeout { .. }) => report.timeouts += 1,
            Err(e) => {
                tracing::warn!("query failed: {e}");
                report.errors += 1;
            }
        }
        if let Some(rest) = period.checked_sub(started.elapsed()) {
            std::thread::sleep(rest);
        }
    }
    report
}

impl Report {
    pub fn json(&self, options: &ClientBenchOptions) -> serde_json::Value {
        let r = self;
        serde_json::json!({
            "client": "rust",
            "query": "latest_gesture",
            "cached_p50_us": us(r.cached.percentile(0.5)),
            "cached_p99_us": us(r.cached.percentile(0.99)),
            "solve_p50_us": us(r.solve.percentile(0.5)),
            "solve_p99_us": us(r.solve.percentile(0.99)),
            "cached_count": r.cached.count(),
            "solve_count": r.solve.count(),
            "other_count": r.other,
            "timeouts": r.timeouts,
            "errors": r.errors,
            "rate_hz": options.rate,
            "duration_s": options.duration.as_secs_f64(),
        })
    }

    pub fn table(&self, options: &ClientBenchOptions) -> String {
        let r = self;
        let mut table = Table::new(&["round trip", "count", "p50 us", "p99 us"]);
        let cell = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.1}"));
        for (name, s) in [
            ("cached answer", &r.cached),
            ("answer after a solve", &r.solve),
        ] {
            table.row(vec![
                name.to_owned(),
                s.count().to_string(),
                cell(s.percentile(0.5)),
                cell(s.percentile(0.99)),
            ]);
        }
        format!(
            "latest-gesture queries at {} /s for {:?}\n{table}other answers {}, timeouts {}, errors {}\n",
            options.rate, options.duration, r.other, r.timeouts, r.errors
        )
    }
}
