//! `vref demo`: the three services with synthetic feeds, pointing gestures
//! at known objects, every answer checked against the world's truth.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context, anyhow, bail};
use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;
use vref_config::Config;
use vref_feed::synthetic_world;
use vref_scene::Side;
use vref_sim::{Gesture, LiveWorld};
use vref_wire::ipc::{ReferenceClient, now_ns};
use vref_wire::{AnswerStatus, ReferenceAnswer};

use crate::cli::DemoArgs;
use crate::failure::{Blame, Failure};
use crate::stdout;

/// How long the services may take to give a first answer.
const READY_WITHIN: Duration = Duration::from_secs(30);
/// How long a service may take to stop after SIGTERM.
const STOP_WITHIN: Duration = Duration::from_secs(10);
/// One query's time limit.
const QUERY_TIMEOUT: Duration = Duration::from_secs(1);
const SERVICES: [&str; 3] = ["vref-matcher", "vref-perception-feed", "vref-gesture-feed"];

pub fn run(args: &DemoArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    // The world the feeds publish, computed here too: it is the truth the
    // answers are checked against.
    let (_, world) = synthetic_world(&config.feeds, args.objects).bad_input()?;
    let binaries = SERVICES
        .iter()
        .map(|name| sibling(name))
        .collect::<anyhow::Result<Vec<_>>>()
        .runtime()?;

    // Its own root path and prefix: the demo never meets, or disturbs,
    // services already running on this machine.
    let dir = tempfile::Builder::new()
        .prefix("vref-demo-")
        .tempdir()
        .runtime()?;
    let demo_config = isolated(&config, dir.path()).runtime()?;
    let config_path = dir.path().join("vref.toml");
    let text = toml::to_string(&demo_config)
        .context("writing the demo configuration")
        .runtime()?;
    std::fs::write(&config_path, text).runtime()?;

    let mut services =
        Services::start(&binaries, &config_path, args.objects, dir.path()).runtime()?;
    let outcome = query_loop(args, &demo_config, &world);
    let stopped = services.stop();
    let summary = outcome.runtime()?;
    if args.json {
        stdout::print(&format!("{}\n", summary.json()))?;
    } else {
        stdout::print(&summary.table())?;
    }
    stopped.runtime()
}

/// A binary installed beside this one.
fn sibling(name: &str) -> anyhow::Result<PathBuf> {
    let exe = std::env::current_exe().context("locating vref")?;
    let path = exe.with_file_name(name);
    if !path.exists() {
        bail!(
            "{} not found beside {}: build every service first (cargo build --release)",
            name,
            exe.display()
        );
    }
    Ok(path)
}

fn isolated(config: &Config, dir: &Path) -> anyhow::Result<Config> {
    let root = dir.join("iceoryx2");
    std::fs::create_dir_all(&root)?;
    let mut demo = config.clone();
    demo.ipc.root_path = Some(root);
    demo.ipc.prefix = format!("vdemo{}_", std::process::id());
    Ok(demo)
}

/// The three service processes; stopped with SIGTERM, killed if they
/// hang.
struct Services {
    children: Vec<(String, Child)>,
    logs: PathBuf,
}

impl Services {
    fn start(
        binaries: &[PathBuf],
        config: &Path,
        objects: Option<usize>,
        logs: &Path,
    ) -> anyhow::Result<Self> {
        let mut services = Services {
            children: Vec::new(),
            logs: logs.to_owned(),
        };
        for binary in binaries {
            let name = binary
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
            let log = std::fs::File::create(logs.join(format!("{name}.log")))?;
            let mut command = Command::new(binary);
            command.arg("--config").arg(config);
            if let (Some(n), true) = (objects, name.ends_with("feed")) {
                command.arg("--objects").arg(n.to_string());
            }
            let child = command
                .stdin(Stdio::null())
                .stdout(log.try_clone()?)
                .stderr(log)
                .spawn()
                .with_context(|| format!("starting {}", binary.display()))?;
            tracing::info!(service = %name, pid = child.id(), "started");
            services.children.push((name, child));
        }
        Ok(services)
    }

    /// SIGTERM to each, then waits; a service that does not stop in time
    /// is killed and reported.
    fn stop(&mut self) -> anyhow::Result<()> {
        let mut problems = Vec::new();
        for (name, child) in &mut self.children {
            let pid = Pid::from_raw(i32::try_from(child.id()).unwrap_or(i32::MAX));
            kill(pid, Signal::SIGTERM).ok();
            let deadline = Instant::now() + STOP_WITHIN;
            let status = loop {
                match child.try_wait() {
                    Ok(Some(status)) => break Some(status),
                    Ok(None) if Instant::now() < deadline => {
                        std::thread::sleep(Duration::from_millis(20))
                    }
                    _ => break None,
                }
            };
            match status {
                Some(s) if s.success() => tracing::info!(service = %name, "stopped"),
                Some(s) => problems.push(format!("{name} exited with {s}")),
                None => {
                    child.kill().ok();
                    child.wait().ok();
                    problems.push(format!(
                        "{name} did not stop within {STOP_WITHIN:?} and was killed"
                    ));
                }
            }
        }
        self.children.clear();
        if problems.is_empty() {
            Ok(())
        } else {
            Err(anyhow!(
                "{} (logs in {})",
                problems.join("; "),
                self.logs.display()
            ))
        }
    }
}

impl Drop for Services {
    fn drop(&mut self) {
        if !self.children.is_empty() {
            self.stop().ok();
        }
    }
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
struct Summary {
    queries: u64,
    answered: u64,
    correct: u64,
    errors: u64,
    by_status: [u64; 6],
    rtt_us: Vec<u64>,
}

impl Summary {
    fn accuracy(&self) -> f64 {
        if self.answered == 0 {
            0.0
        } else {
            self.correct as f64 / self.answered as f64
        }
    }

    fn percentile(&self, q: f64) -> u64 {
        let mut sorted = self.rtt_us.clone();
        sorted.sort_unstable();
        match sorted.len() {
            0 => 0,
            n => sorted[((n - 1) as f64 * q).round() as usize],
        }
    }

    fn json(&self) -> String {
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
        };
        serde_json::to_string(&line).unwrap_or_default()
    }

    fn table(&self) -> String {
        let statuses: Vec<String> = AnswerStatus::ALL
            .iter()
            .filter(|s| self.by_status[**s as usize] > 0)
            .map(|s| format!("{} {}", s.name(), self.by_status[*s as usize]))
            .collect();
        format!(
            "\nqueries {}, answered {}, correct {}, accuracy {:.3}, errors {}\n\
             statuses: {}\nanswer round trip: p50 {} us, p99 {} us\n",
            self.queries,
            self.answered,
            self.correct,
            self.accuracy(),
            self.errors,
            statuses.join(", "),
            self.percentile(0.5),
            self.percentile(0.99),
        )
    }
}

fn now_s() -> f64 {
    now_ns() as f64 / 1e9
}

/// Waits for the services, then points at the gesture target of the
/// moment at the query rate until the duration is over.
fn query_loop(args: &DemoArgs, config: &Config, world: &LiveWorld) -> anyhow::Result<Summary> {
    let mut client =
        ReferenceClient::connect(&config.ipc, &format!("vref-demo-{}", std::process::id()))?;
    wait_ready(&mut client, world)?;
    let period = Duration::from_secs_f64(1.0 / args.query_rate);
    let end = Instant::now() + args.duration;
    let mut summary = Summary::default();
    while Instant::now() < end {
        let tick = Instant::now();
        let t = now_s();
        if let Some(gesture) = world.gesture(t) {
            let expected = world
                .detected(Side::Robot, t)
                .contains(&gesture.target)
                .then_some(gesture.robot_id);
            summary.queries += 1;
            let asked = Instant::now();
            match ask(&mut client, &gesture) {
                Ok(answer) => {
                    let rtt = u64::try_from(asked.elapsed().as_micros()).unwrap_or(u64::MAX);
                    let right = is_right(&answer, expected);
                    summary.answered += 1;
                    summary.correct += u64::from(right);
                    summary.by_status[answer.status() as usize] += 1;
                    summary.rtt_us.push(rtt);
                    if !args.json {
                        stdout::print(&line(t, &gesture, expected, &answer, right, rtt))
                            .map_err(|f| anyhow!("{:#}", f.error()))?;
                    }
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

fn ask(
    client: &mut ReferenceClient,
    g: &Gesture,
) -> Result<ReferenceAnswer, vref_wire::ipc::IpcError> {
    let origin = g.origin.coords.map(|v| v as f32).into();
    let direction = g.direction.map(|v| v as f32).into();
    client.by_ray(origin, direction, g.cone_half_angle as f32, QUERY_TIMEOUT)
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

fn line(
    t: f64,
    g: &Gesture,
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
    format!(
        "t={:.1}s pointed at human {} (truth: {truth}) -> {} robot {} confidence {:.2}: {verdict} ({rtt} us)\n",
        t % 1000.0,
        g.human_id,
        a.status().name(),
        a.robot_track_id,
        a.confidence,
    )
}

fn wait_ready(client: &mut ReferenceClient, world: &LiveWorld) -> anyhow::Result<()> {
    let deadline = Instant::now() + READY_WITHIN;
    while Instant::now() < deadline {
        if let Some(g) = world.gesture(now_s())
            && let Ok(answer) = ask(client, &g)
            && !matches!(
                answer.status(),
                AnswerStatus::NotReady | AnswerStatus::Stale
            )
        {
            return Ok(());
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    bail!("the services gave no answer within {READY_WITHIN:?}")
}
