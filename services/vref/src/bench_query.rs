//! `vref bench query`: reference-query round trips against live services,
//! all of them and split by whether the answer came from a solution the
//! client had seen before ("cached") or from one published since its
//! previous answer ("after a solve": the first answer from a new
//! solution), beside the bare iceoryx2 request/response round trip
//! measured in the same run. With `--compare-idle`, the same first with
//! the feeds stopped (an idle matcher), so that what solves running
//! beside the queries cost them shows.
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
use iceoryx2::waitset::WaitSetRunResult;
use vref_config::Config;
use vref_feed::synthetic_world;
use vref_scene::Side;
use vref_sim::LiveWorld;
use vref_wire::ipc::{
    DecisionReader, IpcSettings, ReferenceClient, answer_waiting, create_node, now_ns,
    open_answer_event, open_reference, open_request_event,
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
    if args.with_viewer {
        // A viewer as a person would run one: live server (no client) and
        // an MCAP file of everything, raw wire messages included.
        let mut command = std::process::Command::new(&vref);
        command
            .args(["view", "--listen", "127.0.0.1:0", "--mcap"])
            .arg(dir.path().join("view.mcap"))
            .arg("--config")
            .arg(&config_path);
        echo.spawn("vref-view", command).runtime()?;
    }
    let mut system =
        Services::start_system(&binaries, &config_path, Some(args.objects), dir.path())
            .runtime()?;
    let restart = Restart {
        binaries: &binaries,
        config: &config_path,
        objects: args.objects,
    };
    let outcome = run_phases(args, &own, &world, &mut system, &mut echo, &restart);
    let stopped = system.stop().and(echo.stop());
    keep_logs_if(outcome.is_err() || stopped.is_err(), dir);
    let (report, idle) = outcome.runtime()?;
    let text = if args.json {
        format!("{}\n", report.json(args, &config, idle.as_ref()))
    } else {
        report.table(args, &config, idle.as_ref())
    };
    stdout::print(&text)?;
    stopped.runtime()
}

/// Round trips of one kind, microseconds.
#[derive(Debug, Default)]
pub(crate) struct Samples(Vec<f64>);

impl Samples {
    pub(crate) fn push(&mut self, d: Duration) {
        self.0.push(d.as_secs_f64() * 1e6);
    }

    pub(crate) fn count(&self) -> usize {
        self.0.len()
    }

    /// Nearest-rank percentile (vref_measure's one definition); `None`
    /// without samples.
    pub(crate) fn percentile(&self, q: f64) -> Option<f64> {
        let mut sorted = self.0.clone();
        sorted.sort_by(f64::total_cmp);
        vref_measure::percentile(&sorted, q)
    }
}

/// What one run measured.
#[derive(Debug, Default)]
struct Report {
    /// Every matcher answer, whatever its status.
    all: Samples,
    cached: Samples,
    solve: Samples,
    bare: Samples,
    /// The matcher's solve times, from its published decisions.
    solve_times: Samples,
    /// The (robot, human) sequences of the last matcher answer.
    last_solution: Option<(u64, u64)>,
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

/// The feeds, which `--compare-idle` stops for its idle phase.
const FEEDS: [&str; 2] = ["vref-perception-feed", "vref-gesture-feed"];

/// How to start the feeds again after the idle phase.
struct Restart<'a> {
    binaries: &'a [std::path::PathBuf],
    config: &'a std::path::Path,
    objects: usize,
}
/// How long a phase change settles before measuring.
const SETTLE: Duration = Duration::from_millis(500);

/// The busy run, and the idle one before it with `--compare-idle`.
fn run_phases(
    args: &BenchQueryArgs,
    config: &Config,
    world: &LiveWorld,
    system: &mut Services,
    echo: &mut Services,
    restart: &Restart<'_>,
) -> anyhow::Result<(Report, Option<Report>)> {
    let pid = std::process::id();
    let mut clients = Clients {
        matcher: ReferenceClient::connect(&config.ipc, &format!("vref-bench-query-{pid}"))?,
        bare: ReferenceClient::connect(
            &echo_settings(&config.ipc),
            &format!("vref-bench-bare-{pid}"),
        )?,
        decisions: DecisionReader::connect(&config.ipc, &format!("vref-bench-decisions-{pid}"))?,
    };
    let both = |system: &mut Services, echo: &mut Services| {
        system.ensure_running()?;
        echo.ensure_running()
    };
    wait_ready(&mut clients.matcher, &mut clients.bare, world, &mut || {
        both(system, echo)
    })?;
    let idle = if args.compare_idle {
        // Stopped, not paused: a feed takes any signal in its sleep as one
        // to stop. Started again afterwards, with new sessions.
        for feed in FEEDS {
            system.stop_one(feed)?;
        }
        std::thread::sleep(SETTLE);
        let idle = measure(args, &mut clients, world, &mut || Ok(()));
        system.start_some(
            restart.binaries,
            restart.config,
            &["--objects".to_owned(), restart.objects.to_string()],
            |name| FEEDS.contains(&name),
        )?;
        wait_ready(&mut clients.matcher, &mut clients.bare, world, &mut || {
            both(system, echo)
        })?;
        std::thread::sleep(SETTLE);
        Some(idle?)
    } else {
        None
    };
    let busy = measure(args, &mut clients, world, &mut || both(system, echo))?;
    Ok((busy, idle))
}

struct Clients {
    matcher: ReferenceClient,
    bare: ReferenceClient,
    decisions: DecisionReader,
}

fn measure(
    args: &BenchQueryArgs,
    clients: &mut Clients,
    world: &LiveWorld,
    running: &mut dyn FnMut() -> anyhow::Result<()>,
) -> anyhow::Result<Report> {
    let Clients {
        matcher,
        bare,
        decisions,
    } = clients;
    // Decisions from before this phase are not its solves.
    decisions.latest()?;
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
        if let Some(Ok(decision)) = decisions.latest()? {
            report
                .solve_times
                .push(Duration::from_micros(decision.header.solve_us));
        }
        tick += 1;
        if tick.is_multiple_of(100) {
            running()?;
        }
        if let Some(rest) = period.checked_sub(started.elapsed()) {
            std::thread::sleep(rest);
        }
    }
    Ok(report)
}

fn classify(report: &mut Report, answer: &ReferenceAnswer, took: Duration) {
    report.all.push(took);
    let solution = (answer.robot_sequence, answer.human_sequence);
    let new = report.last_solution.is_some_and(|last| last != solution);
    report.last_solution = Some(solution);
    match answer.status() {
        // Only these went through the solution (queries name a human
        // object, so `no_match` is the solution's "no partner"); the
        // snapshots they name tell a solution new since the last answer.
        AnswerStatus::Ok | AnswerStatus::Ambiguous | AnswerStatus::NoMatch => {
            if new {
                report.solve.push(took);
            } else {
                report.cached.push(took);
            }
        }
        other => report.other[other as usize] += 1,
    }
}

fn failed(report: &mut Report, error: &vref_wire::ipc::IpcError) {
    if matches!(
        error,
        vref_wire::ipc::IpcError::Timeout { .. } | vref_wire::ipc::IpcError::NoServer { .. }
    ) {
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
            // Any answer from a solution, stale too: a configuration whose
            // solves are slow is measured, not refused here.
            matcher_ready = matcher.by_human_object(id, QUERY_TIMEOUT).is_ok_and(|a| {
                matches!(
                    a.status(),
                    AnswerStatus::Ok
                        | AnswerStatus::Ambiguous
                        | AnswerStatus::NoMatch
                        | AnswerStatus::Stale
                )
            });
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
pub(crate) fn us(value: Option<f64>) -> serde_json::Value {
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

    fn json(
        &self,
        args: &BenchQueryArgs,
        config: &Config,
        idle: Option<&Report>,
    ) -> serde_json::Value {
        let p = |s: &Samples, q| us(s.percentile(q));
        let mut json = serde_json::json!({
            "objects": args.objects,
            "all_p50_us": p(&self.all, 0.5),
            "all_p99_us": p(&self.all, 0.99),
            "ratio_all_p99": ratio(self.all.percentile(0.99), self.bare.percentile(0.99)),
            "all_p999_us": p(&self.all, 0.999),
            "all_count": self.all.count(),
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
            "solve_time_p50_us": p(&self.solve_times, 0.5),
            "solve_time_p99_us": p(&self.solve_times, 0.99),
            "solve_time_count": self.solve_times.count(),
            "method": config.matcher.method,
            "tier": config.matcher.tier,
            "rate_hz": args.rate,
            "duration_s": args.duration.as_secs_f64(),
            "human_objects_mean": (self.mean_human_objects() * 10.0).round() / 10.0,
            "with_viewer": args.with_viewer,
        });
        if let (Some(idle), Some(fields)) = (idle, json.as_object_mut()) {
            fields.insert("idle_all_p50_us".to_owned(), p(&idle.all, 0.5));
            fields.insert("idle_all_p99_us".to_owned(), p(&idle.all, 0.99));
            fields.insert("idle_bare_p99_us".to_owned(), p(&idle.bare, 0.99));
            fields.insert(
                "ratio_busy_idle_p99".to_owned(),
                serde_json::json!(ratio(self.all.percentile(0.99), idle.all.percentile(0.99))),
            );
        }
        json
    }

    fn table(&self, args: &BenchQueryArgs, config: &Config, idle: Option<&Report>) -> String {
        let mut table = Table::new(&["round trip", "count", "p50 us", "p99 us", "p99.9 us"]);
        let cell = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.1}"));
        let mut rows = vec![
            ("every matcher answer", &self.all),
            ("cached answer", &self.cached),
            ("first answer from a new solution", &self.solve),
            ("bare iceoryx2", &self.bare),
            ("(the matcher's solve times)", &self.solve_times),
        ];
        if let Some(idle) = idle {
            rows.push(("every answer, idle matcher", &idle.all));
            rows.push(("bare iceoryx2, idle matcher", &idle.bare));
        }
        for (name, s) in rows {
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
             {} queries/s for {:?}\n{table}cached / bare: p50 {}, p99 {}; all / bare p99 {}\n\
             other answers {}, timeouts {}, errors {}\n",
            args.objects,
            self.mean_human_objects(),
            config.matcher.method,
            args.rate,
            args.duration,
            r(0.5),
            r(0.99),
            ratio(self.all.percentile(0.99), self.bare.percentile(0.99))
                .map_or_else(|| "-".to_owned(), |v| format!("{v:.2}")),
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
        let done = answer_waiting(&server, |q, _| Some(echo(q)), |_| {});
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
    let mut on_event = on_event;
    let result = loop {
        match waitset.wait_and_process(&mut on_event) {
            Ok(WaitSetRunResult::Interrupt) => continue,
            other => break other.map_err(|e| anyhow!("waiting: {e:?}"))?,
        }
    };
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
    fn answers_are_sorted_by_whether_their_solution_is_new_and_by_status() {
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
        // A solution of newer snapshots.
        answer.robot_sequence = 2;
        answer.status = AnswerStatus::Ambiguous as u32;
        classify(&mut report, &answer, Duration::from_micros(1));
        // "No partner" comes from the solution too.
        answer.human_sequence = 2;
        answer.status = AnswerStatus::NoMatch as u32;
        classify(&mut report, &answer, Duration::from_micros(1));
        assert_eq!(
            (
                report.cached.count(),
                report.solve.count(),
                report.other_total(),
                report.all.count()
            ),
            (1, 2, 1, 4)
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
