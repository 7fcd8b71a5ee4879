//! `vref bench query`: reference-query round trips against live services,
//! split by whether the matcher answered from its cached solution or had
//! to solve first, beside the bare iceoryx2 request/response round trip
//! measured in the same run.
//!
//! The bare round trip is served by `vref bench echo-server`, a separate
//! process like the matcher, on the same services (ReferenceQuery to
//! ReferenceAnswer, request and answer events, created by the same
//! functions) under its own namespace, and asked through the same
//! [`ReferenceClient`]: the only difference between the two is what the
//! server does between receiving and answering. It is a hidden subcommand
//! of `vref` rather than a matcher flag so that the matcher carries no
//! benchmark code and the echo's WaitSet holds only the request event.

use std::time::{Duration, Instant};

use anyhow::{Context, anyhow, bail};
use iceoryx2::prelude::*;
use vref_config::Config;
use vref_feed::synthetic_world;
use vref_scene::Side;
use vref_sim::LiveWorld;
use vref_wire::ipc::{
    IpcSettings, ReferenceClient, answer_waiting, create_node, now_ns, open_answer_event,
    open_reference, open_request_event,
};
use vref_wire::{AnswerStatus, ReferenceAnswer, ReferenceQuery};

use crate::cli::{BenchQueryArgs, EchoServerArgs};
use crate::failure::{Blame, Failure};
use crate::launch::{Isolation, Services, keep_logs_if, prepare};
use crate::stdout;
use crate::table::Table;

/// How long the services may take to give a first real answer.
const READY_WITHIN: Duration = Duration::from_secs(30);
/// One query's time limit: well above an exact solve at 64 objects on a
/// busy 2-core machine, so that a timeout means something is wrong.
const QUERY_TIMEOUT: Duration = Duration::from_secs(2);
/// How often the list of human objects to ask about is recomputed.
const IDS_EVERY: Duration = Duration::from_millis(100);

/// The echo server's services live under this namespace below the
/// configured one, so they never meet the matcher's.
fn echo_settings(ipc: &IpcSettings) -> IpcSettings {
    let mut echo = ipc.clone();
    echo.namespace = format!("{}/bench-echo", ipc.namespace.trim_end_matches('/'));
    echo
}

pub fn query(args: &BenchQueryArgs) -> Result<(), Failure> {
    if args.objects < 2 {
        return Err(anyhow!("--objects: at least 2")).bad_input();
    }
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let (_, world) = synthetic_world(&config.feeds, Some(args.objects)).bad_input()?;
    let Isolation {
        binaries,
        dir,
        config: own,
        config_path,
    } = prepare(&config, "bench-query", "vbq").runtime()?;
    let vref = std::env::current_exe().context("locating vref").runtime()?;

    // The echo first: the matcher takes longer to be ready anyway. A
    // failed start stops what was started (Drop).
    let mut echo = Services::new(dir.path());
    let mut command = std::process::Command::new(&vref);
    command
        .args(["bench", "echo-server", "--config"])
        .arg(&config_path);
    echo.spawn("vref-bench-echo", command).runtime()?;
    let mut system =
        Services::start_system(&binaries, &config_path, Some(args.objects), dir.path())
            .runtime()?;
    let mut running = || {
        system.ensure_running()?;
        echo.ensure_running()
    };
    let outcome = measure(args, &own, &world, &mut running);
    let stopped = system.stop().and(echo.stop());
    keep_logs_if(outcome.is_err() || stopped.is_err(), dir);
    let report = outcome.runtime()?;
    let text = if args.json {
        format!("{}\n", report.json(args, &config))
    } else {
        report.table(args, &config)
    };
    stdout::print(&text)?;
    stopped.runtime()
}

/// Round trips of one kind, microseconds.
#[derive(Debug, Default)]
pub struct Samples(Vec<f64>);

impl Samples {
    pub fn push(&mut self, d: Duration) {
        self.0.push(d.as_secs_f64() * 1e6);
    }

    pub fn count(&self) -> usize {
        self.0.len()
    }

    /// Nearest-rank percentile; `None` without samples.
    pub fn percentile(&self, q: f64) -> Option<f64> {
        let mut sorted = self.0.clone();
        sorted.sort_by(f64::total_cmp);
        if sorted.is_empty() {
            return None;
        }
        let rank = (q * sorted.len() as f64).ceil() as usize;
        Some(sorted[rank.clamp(1, sorted.len()) - 1])
    }
}

/// What one run measured.
#[derive(Debug, Default)]
struct Report {
    cached: Samples,
    solve: Samples,
    bare: Samples,
    /// Matcher answers that never reached the solution (no such object
    /// any more, not ready, stale), by status.
    other: [u64; 6],
    timeouts: u64,
    errors: u64,
    /// Human objects asked about, summed over refreshes, and refreshes.
    human_objects: (usize, usize),
}

/// One of the three measurements of a tick.
#[derive(Debug, Clone, Copy)]
enum Probe {
    Matcher,
    Bare,
}

/// Each tick asks the matcher twice and the echo once, in an order that
/// rotates from tick to tick, so that noise falls on all three kinds alike.
/// The second matcher query of a tick usually meets the solution the first
/// one made: that keeps cached answers frequent when solves are slow.
const ORDERS: [[Probe; 3]; 3] = [
    [Probe::Matcher, Probe::Matcher, Probe::Bare],
    [Probe::Matcher, Probe::Bare, Probe::Matcher],
    [Probe::Bare, Probe::Matcher, Probe::Matcher],
];

fn measure(
    args: &BenchQueryArgs,
    config: &Config,
    world: &LiveWorld,
    running: &mut dyn FnMut() -> anyhow::Result<()>,
) -> anyhow::Result<Report> {
    let pid = std::process::id();
    let mut matcher = ReferenceClient::connect(&config.ipc, &format!("vref-bench-query-{pid}"))?;
    let mut bare = ReferenceClient::connect(
        &echo_settings(&config.ipc),
        &format!("vref-bench-bare-{pid}"),
    )?;
    wait_ready(&mut matcher, &mut bare, world, running)?;

    let mut report = Report::default();
    let period = Duration::from_secs_f64(1.0 / args.rate);
    let end = Instant::now() + args.duration;
    let mut ids = Vec::new();
    let mut ids_at: Option<Instant> = None;
    let mut tick = 0usize;
    while Instant::now() < end {
        let started = Instant::now();
        if ids_at.is_none_or(|at| at.elapsed() >= IDS_EVERY) {
            ids = human_ids(world);
            ids_at = Some(Instant::now());
            report.human_objects.0 += ids.len();
            report.human_objects.1 += 1;
        }
        for probe in ORDERS[tick % ORDERS.len()] {
            match probe {
                Probe::Matcher => {
                    let id = ids.get(tick % ids.len().max(1)).copied().unwrap_or(0);
                    let asked = Instant::now();
                    let result = matcher.by_human_object(id, QUERY_TIMEOUT);
                    let took = asked.elapsed();
                    match result {
                        Ok(answer) => classify(&mut report, &answer, took),
                        Err(e) => failed(&mut report, &e),
                    }
                }
                Probe::Bare => {
                    let asked = Instant::now();
                    let result = bare.by_human_object(0, QUERY_TIMEOUT);
                    let took = asked.elapsed();
                    match result {
                        Ok(_) => report.bare.push(took),
                        Err(e) => failed(&mut report, &e),
                    }
                }
            }
        }
        tick += 1;
        if let Some(rest) = period.checked_sub(started.elapsed()) {
            std::thread::sleep(rest);
        }
    }
    Ok(report)
}

fn classify(report: &mut Report, answer: &ReferenceAnswer, took: Duration) {
    match answer.status() {
        // Only these went through the solution (queries name a human
        // object, so `no_match` is the solution's "no partner"); their
        // flag says whether it had to be computed first.
        AnswerStatus::Ok | AnswerStatus::Ambiguous | AnswerStatus::NoMatch => {
            if answer.solved() {
                report.solve.push(took);
            } else {
                report.cached.push(took);
            }
        }
        other => report.other[other as usize] += 1,
    }
}

fn failed(report: &mut Report, error: &vref_wire::ipc::IpcError) {
    if matches!(error, vref_wire::ipc::IpcError::Timeout { .. }) {
        report.timeouts += 1;
    } else {
        report.errors += 1;
    }
    tracing::warn!("query failed: {error}");
}

/// Track ids of the objects the headset sees now: what the gesture feed
/// publishes, so queries about them reach the solution.
pub fn human_ids(world: &LiveWorld) -> Vec<u64> {
    let t = now_ns() as f64 / 1e9;
    world
        .detected(Side::Human, t)
        .into_iter()
        .filter_map(|k| world.track_id(Side::Human, k))
        .collect()
}

fn wait_ready(
    matcher: &mut ReferenceClient,
    bare: &mut ReferenceClient,
    world: &LiveWorld,
    running: &mut dyn FnMut() -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let deadline = Instant::now() + READY_WITHIN;
    let mut matcher_ready = false;
    let mut bare_ready = false;
    while Instant::now() < deadline {
        running()?;
        if !matcher_ready && let Some(&id) = human_ids(world).first() {
            matcher_ready = matcher
                .by_human_object(id, QUERY_TIMEOUT)
                .is_ok_and(|a| matches!(a.status(), AnswerStatus::Ok | AnswerStatus::Ambiguous));
        }
        if !bare_ready {
            bare_ready = bare.by_human_object(0, QUERY_TIMEOUT).is_ok();
        }
        if matcher_ready && bare_ready {
            return Ok(());
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    bail!(
        "no answer within {READY_WITHIN:?} from {}",
        match (matcher_ready, bare_ready) {
            (false, false) => "the matcher and the echo server",
            (false, true) => "the matcher",
            _ => "the echo server",
        }
    )
}

/// Microseconds to one decimal, `null` without samples.
pub fn us(value: Option<f64>) -> serde_json::Value {
    value.map_or(serde_json::Value::Null, |v| {
        serde_json::json!((v * 10.0).round() / 10.0)
    })
}

fn ratio(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) if b > 0.0 => Some((a / b * 1000.0).round() / 1000.0),
        _ => None,
    }
}

impl Report {
    fn other_total(&self) -> u64 {
        self.other.iter().sum()
    }

    fn mean_human_objects(&self) -> f64 {
        let (sum, n) = self.human_objects;
        if n == 0 { 0.0 } else { sum as f64 / n as f64 }
    }

    fn json(&self, args: &BenchQueryArgs, config: &Config) -> serde_json::Value {
        let p = |s: &Samples, q| us(s.percentile(q));
        serde_json::json!({
            "objects": args.objects,
            "cached_p50_us": p(&self.cached, 0.5),
            "cached_p99_us": p(&self.cached, 0.99),
            "solve_p50_us": p(&self.solve, 0.5),
            "solve_p99_us": p(&self.solve, 0.99),
            "bare_p50_us": p(&self.bare, 0.5),
            "bare_p99_us": p(&self.bare, 0.99),
            "ratio_p99": ratio(self.cached.percentile(0.99), self.bare.percentile(0.99)),
            "cached_p999_us": p(&self.cached, 0.999),
            "solve_p999_us": p(&self.solve, 0.999),
            "bare_p999_us": p(&self.bare, 0.999),
            "ratio_p50": ratio(self.cached.percentile(0.5), self.bare.percentile(0.5)),
            "cached_count": self.cached.count(),
            "solve_count": self.solve.count(),
            "bare_count": self.bare.count(),
            "other_count": self.other_total(),
            "timeouts": self.timeouts,
            "errors": self.errors,
            "method": config.matcher.method,
            "rate_hz": args.rate,
            "duration_s": args.duration.as_secs_f64(),
            "human_objects_mean": (self.mean_human_objects() * 10.0).round() / 10.0,
        })
    }

    fn table(&self, args: &BenchQueryArgs, config: &Config) -> String {
        let mut table = Table::new(&["round trip", "count", "p50 us", "p99 us", "p99.9 us"]);
        let cell = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.1}"));
        for (name, s) in [
            ("cached answer", &self.cached),
            ("answer after a solve", &self.solve),
            ("bare iceoryx2", &self.bare),
        ] {
            table.row(vec![
                name.to_owned(),
                s.count().to_string(),
                cell(s.percentile(0.5)),
                cell(s.percentile(0.99)),
                cell(s.percentile(0.999)),
            ]);
        }
        let r = |q| {
            ratio(self.cached.percentile(q), self.bare.percentile(q))
                .map_or_else(|| "-".to_owned(), |v| format!("{v:.2}"))
        };
        format!(
            "{} objects in the world ({:.1} seen by the headset on average), method {}, \
             {} queries/s for {:?}\n{table}cached / bare: p50 {}, p99 {}\n\
             other answers {}, timeouts {}, errors {}\n",
            args.objects,
            self.mean_human_objects(),
            config.matcher.method,
            args.rate,
            args.duration,
            r(0.5),
            r(0.99),
            self.other_total(),
            self.timeouts,
            self.errors,
        )
    }
}

/// `vref bench echo-server`: answers every reference query at once with
/// an empty answer carrying its request id, on the echo namespace, with
/// the matcher's wake-ups (request event in a WaitSet, answer event after
/// sending). Runs until SIGINT or SIGTERM.
pub fn echo_server(args: &EchoServerArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    serve_echo(&echo_settings(&config.ipc)).runtime()
}

fn serve_echo(ipc: &IpcSettings) -> anyhow::Result<()> {
    let node = create_node(ipc, "vref-bench-echo")?;
    node.try_cleanup_dead_nodes();
    let server = open_reference(&node, ipc)?
        .server_builder()
        .create()
        .map_err(|e| anyhow!("creating the echo server: {e:?}"))?;
    let requests = open_request_event(&node, ipc)?
        .listener_builder()
        .create()
        .map_err(|e| anyhow!("creating the request listener: {e:?}"))?;
    let answers = open_answer_event(&node, ipc)?
        .notifier_builder()
        .create()
        .map_err(|e| anyhow!("creating the answer notifier: {e:?}"))?;
    let waitset = WaitSetBuilder::new()
        .create::<ipc::Service>()
        .map_err(|e| anyhow!("creating the WaitSet: {e:?}"))?;
    let _guard = waitset
        .attach_notification(&requests)
        .map_err(|e| anyhow!("attaching to the WaitSet: {e:?}"))?;
    tracing::info!(namespace = %ipc.namespace, "echo server ready");
    let mut served = 0u64;
    let on_event = |_: WaitSetAttachmentId<ipc::Service>| {
        if let Err(e) = requests.try_wait(|_| {}) {
            tracing::warn!("draining the request listener: {e:?}");
        }
        let done = answer_waiting(&server, echo, |_| {});
        for failure in &done.failures {
            tracing::warn!("{failure}");
        }
        served += done.sent;
        let any = done.sent > 0;
        if any && let Err(e) = answers.notify() {
            tracing::warn!("notifying answers: {e:?}");
        }
        CallbackProgression::Continue
    };
    let result = waitset
        .wait_and_process(on_event)
        .map_err(|e| anyhow!("waiting: {e:?}"))?;
    tracing::info!(?result, served, "echo server stopped");
    Ok(())
}

/// The answer the echo gives: the request back, nothing looked up.
fn echo(query: &ReferenceQuery) -> ReferenceAnswer {
    ReferenceAnswer {
        human_object_id: query.human_object_id,
        ..ReferenceAnswer::empty(query.request_id, AnswerStatus::NoMatch)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    #[test]
    fn percentiles_are_nearest_rank_and_none_when_empty() {
        let mut s = Samples::default();
        assert_eq!(s.percentile(0.5), None);
        for v in [5, 1, 4, 2, 3] {
            s.push(Duration::from_micros(v));
        }
        assert_eq!(s.percentile(0.5), Some(3.0));
        assert_eq!(s.percentile(0.99), Some(5.0));
        assert_eq!(s.percentile(0.0), Some(1.0));
    }

    #[test]
    fn answers_are_sorted_by_their_solved_flag_and_status() {
        let mut report = Report::default();
        let mut answer = echo(&ReferenceQuery {
            request_id: 3,
            human_object_id: 1,
            ray_origin: [0.0; 3],
            ray_direction: [0.0; 3],
            cone_half_angle: 0.0,
            kind: 0,
            schema_version: vref_wire::SCHEMA_VERSION,
            reserved: 0,
        });
        assert_eq!(answer.request_id, 3);
        // Never reached the solution.
        answer.status = AnswerStatus::BadRequest as u32;
        classify(&mut report, &answer, Duration::from_micros(1));
        answer.status = AnswerStatus::Ok as u32;
        classify(&mut report, &answer, Duration::from_micros(1));
        answer.flags = ReferenceAnswer::FLAG_SOLVED;
        answer.status = AnswerStatus::Ambiguous as u32;
        classify(&mut report, &answer, Duration::from_micros(1));
        // "No partner" comes from the solution too.
        answer.status = AnswerStatus::NoMatch as u32;
        classify(&mut report, &answer, Duration::from_micros(1));
        assert_eq!(
            (
                report.cached.count(),
                report.solve.count(),
                report.other_total()
            ),
            (1, 2, 1)
        );
    }

    #[test]
    fn the_echo_namespace_is_apart_from_the_matchers() {
        let ipc = IpcSettings::default();
        let echo = echo_settings(&ipc);
        assert_ne!(echo.namespace, ipc.namespace);
        assert!(echo.namespace.starts_with(&ipc.namespace));
        assert_eq!((echo.prefix, echo.root_path), (ipc.prefix, ipc.root_path));
    }

    #[test]
    fn ratio_is_cached_over_bare_and_none_without_both() {
        assert_eq!(ratio(Some(130.0), Some(100.0)), Some(1.3));
        assert_eq!(ratio(None, Some(100.0)), None);
        assert_eq!(ratio(Some(1.0), Some(0.0)), None);
    }
}
