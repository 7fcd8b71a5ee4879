//! `vref bench query`: reference-query round trips against live services,
//! all of them and split by whether the answer came from a solution the
//! client had seen before ("cached") or from one published since its
//! previous answer ("after a solve": the first answer from a new
//! solution), beside the bare iceoryx2 request/response round trip
//! measured in the same run. With `--compare-idle`, the same first with
//! an idle matcher, so that what solves running beside the queries cost
//! them shows: the feeds run as in the busy phase but publish under a
//! namespace the matcher does not hear. Both phases then carry the same
//! feed load (on a 2-core machine two synthetic feeds at 30 Hz raise every
//! round trip's p99, the bare one too, several times over), and only the
//! matcher's work differs.
//!
//! [`run`] returns the [`Report`] of the busy run (and of the idle one).
//!
//! The bare round trip is served by `vref bench echo-server`, a separate
//! process like the matcher, on the same services (ReferenceQuery to
//! ReferenceAnswer, request and answer events, created by the same
//! functions) under its own namespace, and asked through the same
//! `ReferenceClient`: the only difference between the two is what the
//! server does between receiving and answering. It is a hidden subcommand
//! of `vref` rather than a matcher flag so that the matcher carries no
//! benchmark code and the echo's WaitSet holds only the request event.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use vref_config::Config;
use vref_feed::synthetic_world;
use vref_scene::Side;
use vref_sim::LiveWorld;
use vref_wire::ipc::{DecisionReader, ReferenceClient, SnapshotWatch, now_ns};
use vref_wire::{AnswerStatus, ReferenceAnswer};

use crate::Finished;
use crate::RunError;
use crate::echo::echo_settings;
use crate::launch::{FEEDS, LaunchError, Services, prepare, write_config_as};
use crate::ready::{READY_WITHIN, Readiness, ReadyError, wait_ready};
use crate::samples::{Samples, ratio, us};

/// One query's time limit: well above an exact solve at 64 objects on a
/// busy 2-core machine, so that a timeout means something is wrong.
const QUERY_TIMEOUT: Duration = Duration::from_secs(2);
/// How often the list of human objects to ask about is recomputed.
const IDS_EVERY: Duration = Duration::from_millis(100);

/// What `vref bench query` was asked.
#[derive(Debug, Clone)]
pub struct QueryBenchOptions {
    /// Objects in the synthetic world, at least 2.
    pub objects: usize,
    /// Also run `vref view` on the services measured.
    pub with_viewer: bool,
    /// Ticks per second.
    pub rate: f64,
    /// How long to measure once the services answer.
    pub duration: Duration,
    /// First measure as long with an idle matcher (the feeds unheard).
    pub compare_idle: bool,
    /// The `vref` binary, which serves the echo (`vref bench echo-server`)
    /// and the viewer (`vref view`).
    pub vref: PathBuf,
}

/// The busy run's report and, with `compare_idle`, the idle run's.
#[derive(Debug)]
pub struct Reports {
    pub busy: Report,
    pub idle: Option<Report>,
}

/// The synthetic world of a benchmark of `objects` objects (at least 2),
/// computed here too: the benchmarks ask about the objects the feeds
/// publish.
pub(crate) fn bench_world(config: &Config, objects: usize) -> Result<LiveWorld, RunError> {
    if objects < 2 {
        return Err(RunError::TooFewObjects);
    }
    Ok(synthetic_world(&config.feeds, Some(objects))?.1)
}

/// Runs the benchmark: the matcher and both feeds from `bin_dir` under
/// `config` isolated, and beside them the echo server (and the viewer).
pub fn run(
    options: &QueryBenchOptions,
    config: &Config,
    bin_dir: &Path,
) -> Result<Finished<Reports>, RunError> {
    let world = bench_world(config, options.objects)?;
    let feed_args = ["--objects".to_owned(), options.objects.to_string()];
    prepare(config, bin_dir, "bench-query", "vbq")?.run_system(
        &feed_args,
        |run, system| {
            // The echo (and the viewer) beside the services, so that one
            // check sees every process die and one stop stops them all.
            let mut command = std::process::Command::new(&options.vref);
            command
                .args(["bench", "echo-server", "--config"])
                .arg(run.config_path);
            system.spawn("vref-bench-echo", command)?;
            if options.with_viewer {
                // A viewer as a person would run one: live server (no
                // client) and an MCAP file of everything, raw wire
                // messages included.
                let mut command = std::process::Command::new(&options.vref);
                command
                    .args(["view", "--listen", "127.0.0.1:0", "--mcap"])
                    .arg(run.dir.join("view.mcap"))
                    .arg("--config")
                    .arg(run.config_path);
                system.spawn("vref-view", command)?;
            }
            let unheard = write_config_as(&unheard(run.config), run.dir, "vref-unheard.toml")?;
            let restart = Restart {
                binaries: run.binaries,
                config: run.config_path,
                unheard: &unheard,
                objects: options.objects,
            };
            let (busy, idle) = run_phases(options, run.config, &world, system, &restart)?;
            Ok(Reports { busy, idle })
        },
        |_, _| (),
    )
}

/// What one run measured.
#[derive(Debug, Default)]
pub struct Report {
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

/// How to start the feeds for the idle phase and again after it.
struct Restart<'a> {
    binaries: &'a [PathBuf],
    config: &'a Path,
    /// The same configuration under a namespace no matcher listens to.
    unheard: &'a Path,
    objects: usize,
}

impl Restart<'_> {
    fn feeds(&self, system: &mut Services, config: &Path) -> Result<(), LaunchError> {
        system.start_some(
            self.binaries,
            config,
            &["--objects".to_owned(), self.objects.to_string()],
            |name| FEEDS.contains(&name),
        )
    }
}

/// `config` with the feeds' services where the matcher does not look.
fn unheard(config: &Config) -> Config {
    let mut unheard = config.clone();
    unheard.ipc.namespace = format!(
        "{}/bench-unheard",
        config.ipc.namespace.trim_end_matches('/')
    );
    unheard
}

/// Returns once the feeds of the idle phase publish: each side's snapshot
/// has been seen under the unheard namespace (`watches`, connected before
/// the feeds started).
fn wait_feeds_publish(
    watches: &[(Side, SnapshotWatch)],
    running: &mut dyn FnMut() -> Result<(), LaunchError>,
) -> Result<(), ReadyError> {
    let mut seen = vec![false; watches.len()];
    wait_ready(READY_WITHIN, Duration::from_millis(50), || {
        running()?;
        for ((_, watch), seen) in watches.iter().zip(seen.iter_mut()) {
            *seen = *seen || watch.latest()?.is_some();
        }
        Ok(match watches.iter().zip(&seen).find(|(_, s)| !**s) {
            None => Readiness::Ready(()),
            Some(((side, _), _)) => {
                Readiness::Waiting(format!("{side:?} snapshot from the unheard feeds"))
            }
        })
    })
}
/// How long a phase change settles before measuring.
const SETTLE: Duration = Duration::from_millis(500);

/// The busy run, and the idle one before it with `--compare-idle`.
fn run_phases(
    args: &QueryBenchOptions,
    config: &Config,
    world: &LiveWorld,
    system: &mut Services,
    restart: &Restart<'_>,
) -> Result<(Report, Option<Report>), RunError> {
    let pid = std::process::id();
    let mut clients = Clients {
        matcher: ReferenceClient::connect(&config.ipc, &format!("vref-bench-query-{pid}"))?,
        bare: ReferenceClient::connect(
            &echo_settings(&config.ipc),
            &format!("vref-bench-bare-{pid}"),
        )?,
        decisions: DecisionReader::connect(&config.ipc, &format!("vref-bench-decisions-{pid}"))?,
    };
    wait_ready_both(&mut clients.matcher, &mut clients.bare, world, &mut || {
        system.ensure_running()
    })?;
    let idle = if args.compare_idle {
        // Stopped, not paused: a feed takes any signal in its sleep as one
        // to stop. Started unheard for the idle phase, then again where
        // the matcher hears them, with new sessions.
        for feed in FEEDS {
            system.stop_one(feed)?;
        }
        let quiet = unheard(config).ipc;
        let watches = [Side::Robot, Side::Human]
            .into_iter()
            .map(|side| {
                let name = format!("vref-bench-watch-{side:?}-{pid}");
                SnapshotWatch::connect(&quiet, side, &name).map(|w| (side, w))
            })
            .collect::<Result<Vec<_>, _>>()?;
        restart.feeds(system, restart.unheard)?;
        wait_feeds_publish(&watches, &mut || system.ensure_running())?;
        drop(watches);
        let idle = measure(args, &mut clients, world, &mut || system.ensure_running());
        for feed in FEEDS {
            system.stop_one(feed)?;
        }
        restart.feeds(system, restart.config)?;
        wait_ready_both(&mut clients.matcher, &mut clients.bare, world, &mut || {
            system.ensure_running()
        })?;
        std::thread::sleep(SETTLE);
        Some(idle?)
    } else {
        None
    };
    let busy = measure(args, &mut clients, world, &mut || system.ensure_running())?;
    Ok((busy, idle))
}

struct Clients {
    matcher: ReferenceClient,
    bare: ReferenceClient,
    decisions: DecisionReader,
}

fn measure(
    args: &QueryBenchOptions,
    clients: &mut Clients,
    world: &LiveWorld,
    running: &mut dyn FnMut() -> Result<(), LaunchError>,
) -> Result<Report, RunError> {
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

fn wait_ready_both(
    matcher: &mut ReferenceClient,
    bare: &mut ReferenceClient,
    world: &LiveWorld,
    running: &mut dyn FnMut() -> Result<(), LaunchError>,
) -> Result<(), ReadyError> {
    let mut matcher_ready = false;
    let mut bare_ready = false;
    wait_ready(READY_WITHIN, Duration::from_millis(100), || {
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
        Ok(match (matcher_ready, bare_ready) {
            (true, true) => Readiness::Ready(()),
            (false, false) => {
                Readiness::Waiting("answer from the matcher and the echo server".to_owned())
            }
            (false, true) => Readiness::Waiting("answer from the matcher".to_owned()),
            (true, false) => Readiness::Waiting("answer from the echo server".to_owned()),
        })
    })
}

impl Report {
    fn other_total(&self) -> u64 {
        self.other.iter().sum()
    }

    fn mean_human_objects(&self) -> f64 {
        let (sum, n) = self.human_objects;
        if n == 0 { 0.0 } else { sum as f64 / n as f64 }
    }

    /// The `--json` object.
    pub fn json(
        &self,
        args: &QueryBenchOptions,
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
            "solve_time_p90_us": p(&self.solve_times, 0.9),
            "solve_time_p95_us": p(&self.solve_times, 0.95),
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
                "idle_solve_time_count".to_owned(),
                serde_json::json!(idle.solve_times.count()),
            );
            fields.insert(
                "ratio_busy_idle_p99".to_owned(),
                serde_json::json!(ratio(self.all.percentile(0.99), idle.all.percentile(0.99))),
            );
        }
        json
    }

    /// The table a person reads.
    pub fn table(
        &self,
        args: &QueryBenchOptions,
        config: &Config,
        idle: Option<&Report>,
    ) -> String {
        let mut table = crate::table::Table::new(&crate::samples::ROW_HEADER);
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
            table.row(s.row(name));
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

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    #[test]
    fn answers_are_sorted_by_whether_their_solution_is_new_and_by_status() {
        let mut report = Report::default();
        let mut answer = crate::echo::echo(&vref_wire::ReferenceQuery {
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

    /// Each ratio divides the figures its name says, over samples whose
    /// percentiles are known (one value each).
    #[test]
    fn the_reports_ratios_divide_the_figures_they_name() {
        let one = |us: u64| {
            let mut s = Samples::default();
            s.push(Duration::from_micros(us));
            s
        };
        let busy = Report {
            all: one(600),
            cached: one(300),
            solve: one(900),
            bare: one(100),
            ..Report::default()
        };
        let idle = Report {
            all: one(200),
            ..Report::default()
        };
        let options = QueryBenchOptions {
            objects: 8,
            with_viewer: false,
            rate: 100.0,
            duration: Duration::from_secs(1),
            compare_idle: true,
            vref: PathBuf::from("vref"),
        };
        let json = busy.json(&options, &Config::default(), Some(&idle));
        let close = |key: &str, expected: f64| {
            let value = json[key].as_f64().unwrap();
            assert!(
                (value - expected).abs() < 1e-9,
                "{key}: {value}, not {expected}"
            );
        };
        close("ratio_p99", 3.0);
        close("ratio_p50", 3.0);
        close("ratio_all_p99", 6.0);
        close("ratio_busy_idle_p99", 3.0);
    }
}
