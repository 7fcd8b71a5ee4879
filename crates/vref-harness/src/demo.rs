//! `vref demo`: the three services with synthetic feeds (or BOP scenes),
//! pointing gestures at known objects, every answer checked against the
//! world's truth. [`run`] returns the [`Summary`]; each answer's line goes
//! to the caller as it comes (the command line prints it).

use std::path::Path;
use std::time::{Duration, Instant};

use vref_config::Config;
use vref_feed::{BopWorld, SourceSpec, synthetic_world};
use vref_scene::Side;
use vref_sim::{Gesture, LiveWorld};
use vref_wire::ipc::ReferenceClient;
use vref_wire::{AnswerStatus, ReferenceAnswer};

use crate::launch::{Services, prepare};
use crate::ready::{READY_WITHIN, Readiness, ReadyError, wait_ready};
use crate::{Finished, OutputError, RunError, now_s};

/// One query's time limit.
const QUERY_TIMEOUT: Duration = Duration::from_secs(1);
/// BOP source: no query in a slot's first moments, while the feeds'
/// snapshots of a new scene reach the matcher (one snapshot period at
/// 30 Hz, and its solve, are well within this), and at most half a slot:
/// with a slot no longer than this (`--hold 1s`: two slots of 0.5 s) the
/// demo would never ask, and report the services as not answering.
const SETTLE_S: f64 = 0.5;

/// What `vref demo` was asked.
#[derive(Debug, Clone)]
pub struct DemoOptions {
    /// What the feeds show: synthetic or bop:DIR.
    pub source: SourceSpec,
    /// BOP source: seconds each scene is shown.
    pub hold_s: f64,
    /// BOP source: which way is up in the datasets' world frame.
    pub world_up: Option<[f64; 3]>,
    /// How long to query once the services are ready.
    pub duration: Duration,
    /// Objects in the synthetic world (default: the preset's draw).
    pub objects: Option<usize>,
    /// Queries per second.
    pub query_rate: f64,
}

/// What the feeds show, computed here too: the truth the answers are
/// checked against.
enum Truth {
    Synthetic(Box<LiveWorld>),
    Bop(BopWorld),
}

/// One pointing gesture and the right answer to it.
struct Pointing {
    human_id: u64,
    origin: [f32; 3],
    direction: [f32; 3],
    cone_half_angle: f32,
    /// The robot object meant, `None` when the robot does not see it.
    expected: Option<u64>,
}

impl Truth {
    /// Where the person points at `t` (seconds since the Unix epoch, the
    /// feeds' epoch), if anywhere.
    fn pointing(&self, t: f64) -> Option<Pointing> {
        match self {
            Truth::Synthetic(world) => {
                let g = world.gesture(t)?;
                let expected = world
                    .detected(Side::Robot, t)
                    .contains(&g.target)
                    .then_some(g.robot_id);
                Some(Pointing {
                    human_id: g.human_id,
                    origin: g.origin.coords.map(|v| v as f32).into(),
                    direction: g.direction.map(|v| v as f32).into(),
                    cone_half_angle: g.cone_half_angle as f32,
                    expected,
                })
            }
            Truth::Bop(world) => {
                let settle_s = SETTLE_S.min(0.5 * world.slot_s());
                let g = world.gesture(t).filter(|g| t - g.since_s >= settle_s)?;
                Some(Pointing {
                    human_id: g.human_id,
                    origin: g.origin.map(|v| v as f32),
                    direction: g.direction.map(|v| v as f32),
                    cone_half_angle: g.cone_half_angle as f32,
                    expected: Some(g.robot_id),
                })
            }
        }
    }
}

/// Runs the demo: the services from `bin_dir` with `config` isolated
/// (its own root path and prefix: it never meets, or disturbs, services
/// already running), queries for `options.duration` once they answer.
/// Each answer's line (ending in a newline) goes to `on_line`; an error
/// from it ends the run.
pub fn run(
    options: &DemoOptions,
    config: &Config,
    bin_dir: &Path,
    on_line: &mut dyn FnMut(&str) -> Result<(), OutputError>,
) -> Result<Finished<Summary>, RunError> {
    let (world, feed_args) = match &options.source {
        SourceSpec::Synthetic => {
            if options.world_up.is_some() {
                return Err(
                    vref_feed::SetupError::WorldUpWithoutBop(options.source.to_string()).into(),
                );
            }
            let (_, world) = synthetic_world(&config.feeds, options.objects)?;
            let feed_args = match options.objects {
                Some(n) => vec!["--objects".to_owned(), n.to_string()],
                None => Vec::new(),
            };
            (Truth::Synthetic(Box::new(world)), feed_args)
        }
        SourceSpec::Bop(dir) => {
            let world = BopWorld::load(
                dir,
                options.world_up,
                config.perception,
                config.scene.limits(),
                options.hold_s,
            )?;
            let mut feed_args = vec![
                "--source".to_owned(),
                format!("bop:{}", dir.display()),
                "--hold".to_owned(),
                vref_measure::format_duration(Duration::from_secs_f64(options.hold_s)),
            ];
            if let Some([x, y, z]) = options.world_up {
                feed_args.extend(["--world-up".to_owned(), format!("{x},{y},{z}")]);
            }
            (Truth::Bop(world), feed_args)
        }
        other => {
            return Err(RunError::DemoSource(other.to_string()));
        }
    };
    prepare(config, bin_dir, "demo", "vdemo")?.run_system(
        &feed_args,
        |run, services| query_loop(options, run.config, &world, services, on_line),
        |_, _| (),
    )
}

/// The `--json` summary; field order is the documented contract's.
#[derive(serde::Serialize)]
struct JsonSummary {
    queries: u64,
    answered: u64,
    correct: u64,
    accuracy: f64,
    rtt_p50_us: u64,
    rtt_p99_us: u64,
    errors: u64,
    statuses: Statuses,
    wrong_pointing: u64,
    wrong_matching: u64,
}

/// Answers by status.
#[derive(serde::Serialize)]
struct Statuses {
    ok: u64,
    ambiguous: u64,
    no_match: u64,
    not_ready: u64,
    stale: u64,
    bad_request: u64,
}

/// Figures of a demo run.
#[derive(Debug, Default)]
pub struct Summary {
    queries: u64,
    answered: u64,
    correct: u64,
    errors: u64,
    by_status: [u64; 6],
    rtt_us: Vec<u64>,
    /// Wrong answers whose ray took another human object than the one
    /// pointed at (the pointing's error, not the matcher's).
    wrong_pointing: u64,
    /// Wrong answers about the object pointed at: the matcher's errors.
    wrong_matching: u64,
}

impl Summary {
    fn accuracy(&self) -> f64 {
        if self.answered == 0 {
            0.0
        } else {
            self.correct as f64 / self.answered as f64
        }
    }

    /// Nearest rank (vref_measure); 0 without answers.
    fn percentile(&self, q: f64) -> u64 {
        vref_measure::percentile_of(&self.rtt_us, q).unwrap_or(0)
    }

    /// The `--json` line (without its newline).
    pub fn json(&self) -> String {
        let count = |s: AnswerStatus| self.by_status[s as usize];
        let statuses = Statuses {
            ok: count(AnswerStatus::Ok),
            ambiguous: count(AnswerStatus::Ambiguous),
            no_match: count(AnswerStatus::NoMatch),
            not_ready: count(AnswerStatus::NotReady),
            stale: count(AnswerStatus::Stale),
            bad_request: count(AnswerStatus::BadRequest),
        };
        let line = JsonSummary {
            queries: self.queries,
            answered: self.answered,
            correct: self.correct,
            accuracy: self.accuracy(),
            rtt_p50_us: self.percentile(0.5),
            rtt_p99_us: self.percentile(0.99),
            errors: self.errors,
            statuses,
            wrong_pointing: self.wrong_pointing,
            wrong_matching: self.wrong_matching,
        };
        serde_json::to_string(&line).unwrap_or_default()
    }

    /// The summary a person reads.
    pub fn table(&self) -> String {
        let statuses: Vec<String> = AnswerStatus::ALL
            .iter()
            .filter(|s| self.by_status[**s as usize] > 0)
            .map(|s| format!("{} {}", s.name(), self.by_status[*s as usize]))
            .collect();
        format!(
            "\nqueries {}, answered {}, correct {}, accuracy {:.3}, errors {}\n\
             statuses: {}\nwrong: the ray took a neighbour {}, about the object meant {}\n\
             answer round trip: p50 {} us, p99 {} us\n",
            self.queries,
            self.answered,
            self.correct,
            self.accuracy(),
            self.errors,
            statuses.join(", "),
            self.wrong_pointing,
            self.wrong_matching,
            self.percentile(0.5),
            self.percentile(0.99),
        )
    }
}

/// Waits for the services, then points at the gesture target of the
/// moment at the query rate until the duration is over.
fn query_loop(
    options: &DemoOptions,
    config: &Config,
    world: &Truth,
    services: &mut Services,
    on_line: &mut dyn FnMut(&str) -> Result<(), OutputError>,
) -> Result<Summary, RunError> {
    let mut client =
        ReferenceClient::connect(&config.ipc, &format!("vref-demo-{}", std::process::id()))?;
    // Ready once a pointing ray is answered with a partner (`ok` or
    // `ambiguous`; a dense scene may never be `ok`): the first answers
    // after start can come from a solve of the feeds' first snapshots that
    // left the object without one (`no_match` to the first query in 1 of
    // 6 runs of `vref demo --duration 4s --objects 8`, right from then
    // on), and the demo measures the services, not their start.
    wait_ready(READY_WITHIN, Duration::from_millis(100), || {
        services.ensure_running()?;
        let answered = world.pointing(now_s()).is_some_and(|g| {
            ask_pointing(&mut client, &g, QUERY_TIMEOUT)
                .is_ok_and(|a| matches!(a.status(), AnswerStatus::Ok | AnswerStatus::Ambiguous))
        });
        Ok::<_, ReadyError>(if answered {
            Readiness::Ready(())
        } else {
            Readiness::Waiting("answer naming a partner for a pointing ray".to_owned())
        })
    })?;
    let period = Duration::from_secs_f64(1.0 / options.query_rate);
    let end = Instant::now() + options.duration;
    let mut summary = Summary::default();
    while Instant::now() < end {
        let tick = Instant::now();
        let t = now_s();
        if let Some(gesture) = world.pointing(t) {
            let expected = gesture.expected;
            summary.queries += 1;
            let asked = Instant::now();
            match ask_pointing(&mut client, &gesture, QUERY_TIMEOUT) {
                Ok(answer) => {
                    let rtt = u64::try_from(asked.elapsed().as_micros()).unwrap_or(u64::MAX);
                    let right = is_right(&answer, expected);
                    summary.answered += 1;
                    summary.correct += u64::from(right);
                    if !right && took_neighbour(&answer, &gesture) {
                        summary.wrong_pointing += 1;
                    } else if !right {
                        summary.wrong_matching += 1;
                    }
                    summary.by_status[answer.status() as usize] += 1;
                    summary.rtt_us.push(rtt);
                    on_line(&line(t, &gesture, expected, &answer, right, rtt))
                        .map_err(RunError::Output)?;
                }
                Err(e) => {
                    summary.errors += 1;
                    tracing::warn!("query failed: {e}");
                }
            }
        }
        if let Some(rest) = period.checked_sub(tick.elapsed()) {
            std::thread::sleep(rest);
        }
    }
    Ok(summary)
}

/// Asks which robot object pointing `p` points at.
fn ask_pointing(
    client: &mut ReferenceClient,
    p: &Pointing,
    timeout: Duration,
) -> Result<ReferenceAnswer, vref_wire::ipc::IpcError> {
    client.by_ray(p.origin, p.direction, p.cone_half_angle, timeout)
}

/// Asks which robot object gesture `g` points at.
pub fn ask(
    client: &mut ReferenceClient,
    g: &Gesture,
    timeout: Duration,
) -> Result<ReferenceAnswer, vref_wire::ipc::IpcError> {
    let origin = g.origin.coords.map(|v| v as f32).into();
    let direction = g.direction.map(|v| v as f32).into();
    client.by_ray(origin, direction, g.cone_half_angle as f32, timeout)
}

/// Right means: the robot object the person pointed at, or `no_match`
/// when the robot does not see it. A stale answer is never right.
fn is_right(answer: &ReferenceAnswer, expected: Option<u64>) -> bool {
    match (answer.status(), expected) {
        (AnswerStatus::Ok | AnswerStatus::Ambiguous, Some(id)) => answer.robot_track_id == id,
        (AnswerStatus::NoMatch, None) => true,
        _ => false,
    }
}

/// Whether the ray of `g` took another human object than the one meant.
fn took_neighbour(answer: &ReferenceAnswer, g: &Pointing) -> bool {
    answer.human_object_id != 0 && answer.human_object_id != g.human_id
}

fn line(
    t: f64,
    g: &Pointing,
    expected: Option<u64>,
    a: &ReferenceAnswer,
    right: bool,
    rtt: u64,
) -> String {
    let truth = expected.map_or_else(
        || "not seen by the robot".to_owned(),
        |id| format!("robot {id}"),
    );
    let verdict = if right { "right" } else { "WRONG" };
    // The ray can take a neighbour of the object meant (a dense scene).
    let took = if took_neighbour(a, g) {
        format!(" (the ray took human {})", a.human_object_id)
    } else {
        String::new()
    };
    format!(
        "t={:.1}s pointed at human {} (truth: {truth}) -> {} robot {}{took} confidence {:.2}: {verdict} ({rtt} us)\n",
        t % 1000.0,
        g.human_id,
        a.status().name(),
        a.robot_track_id,
        a.confidence,
    )
}
