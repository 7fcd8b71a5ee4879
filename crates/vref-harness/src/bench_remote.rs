//! `vref bench remote`: what the network edge costs. One run starts the
//! matcher, both feeds and vref-bridge (on a loopback port of its own) and
//! asks the same questions two ways: over Zenoh through the bridge, as a
//! controller on another computer would, and over iceoryx2 to the matcher
//! directly. The difference of the two is what the bridge and Zenoh add.
//! A third way, a Zenoh queryable in this process that answers at once
//! (`vref_bridge::echo`), is Zenoh's own round trip: the floor under the
//! bridge on this machine.
//!
//! [`run`] returns the [`Report`], which renders itself as the command's
//! JSON line or table.

use std::path::Path;
use std::time::{Duration, Instant};

use vref_bridge::echo::Echo;
use vref_bridge::{Format, NetError, RemoteClient};
use vref_config::{BridgeSettings, Config, ZenohMode};
use vref_sim::LiveWorld;
use vref_wire::ipc::{IpcError, ReferenceClient};
use vref_wire::{AnswerStatus, ReferenceAnswer, ReferenceQuery};

use crate::bench_query::{bench_world, human_ids};
use crate::launch::{self, LaunchError, prepare};
use crate::ready::{READY_WITHIN, Readiness, ReadyError, wait_ready};
use crate::samples::{ROW_HEADER, Samples, us};
use crate::table::Table;
use crate::{Finished, RunError};

/// One query's time limit.
const QUERY_TIMEOUT: Duration = Duration::from_secs(2);

/// What `vref bench remote` was asked for.
#[derive(Debug, Clone)]
pub struct RemoteBenchOptions {
    pub objects: usize,
    /// Ticks per second; each tick sends one remote and one local query.
    pub rate: f64,
    pub duration: Duration,
    /// How remote queries and answers travel.
    pub encoding: Format,
}

/// Runs the benchmark: the matcher, both feeds and the bridge from
/// `bin_dir` under `config` isolated, the bridge listening on a free
/// loopback port.
pub fn run(
    options: &RemoteBenchOptions,
    config: &Config,
    bin_dir: &Path,
) -> Result<Finished<Report>, RunError> {
    let world = bench_world(config, options.objects)?;
    let bridge_binary = launch::binary(bin_dir, "vref-bridge")?;
    let [bridge_port, echo_port] = free_ports()?;
    let endpoint = format!("tcp/127.0.0.1:{bridge_port}");
    let prefix = format!("vref/bench{}", std::process::id());
    let echo_endpoint = format!("tcp/127.0.0.1:{echo_port}");
    let echo_prefix = format!("{prefix}-echo");
    let mut config = config.clone();
    config.bridge = BridgeSettings {
        mode: ZenohMode::Peer,
        listen: vec![endpoint.clone()],
        connect: Vec::new(),
        multicast_scouting: false,
        prefix: prefix.clone(),
        headset_in: false,
        queries_in: true,
        state_out: false,
        // The benchmark must not be cut by the bridge's own limit.
        max_query_rate_hz: 100_000.0,
        ..BridgeSettings::default()
    };
    let feed_args = ["--objects".to_owned(), options.objects.to_string()];
    prepare(&config, bin_dir, "bench-remote", "vbr")?.run_system(
        &feed_args,
        |run, system| {
            let mut command = std::process::Command::new(&bridge_binary);
            command.arg("--config").arg(run.config_path);
            system.spawn("vref-bridge", command)?;
            let _echo = Echo::start(&echo_endpoint, &echo_prefix).map_err(RunError::Echo)?;
            let endpoints = Endpoints {
                bridge: (&endpoint, &prefix),
                echo: (&echo_endpoint, &echo_prefix),
            };
            measure(options, run.config, &world, &endpoints, &mut || {
                system.ensure_running()
            })
        },
        |_, _| (),
    )
}

/// Two loopback ports free a moment ago, for the bridge and the echo to
/// listen on; both are held while the second is found, so they differ.
fn free_ports() -> Result<[u16; 2], RunError> {
    let io = RunError::FreePort;
    let first = std::net::TcpListener::bind("127.0.0.1:0").map_err(io)?;
    let second = std::net::TcpListener::bind("127.0.0.1:0").map_err(io)?;
    Ok([
        first.local_addr().map_err(io)?.port(),
        second.local_addr().map_err(io)?.port(),
    ])
}

/// Where the bridge and the echo listen, and their key prefixes.
struct Endpoints<'a> {
    bridge: (&'a str, &'a str),
    echo: (&'a str, &'a str),
}

/// What one run measured.
#[derive(Debug, Default)]
pub struct Report {
    remote: Samples,
    local: Samples,
    /// Bare Zenoh: the echo's round trip.
    zenoh: Samples,
    /// Answers that did not go through the solution (not ready, stale, ...).
    other: u64,
    timeouts: u64,
    errors: u64,
}

fn answered(a: &ReferenceAnswer) -> bool {
    matches!(
        a.status(),
        AnswerStatus::Ok | AnswerStatus::Ambiguous | AnswerStatus::NoMatch
    )
}

fn measure(
    options: &RemoteBenchOptions,
    config: &Config,
    world: &LiveWorld,
    endpoints: &Endpoints<'_>,
    running: &mut dyn FnMut() -> Result<(), LaunchError>,
) -> Result<Report, RunError> {
    let pid = std::process::id();
    let mut local = ReferenceClient::connect(&config.ipc, &format!("vref-bench-local-{pid}"))?;
    let (endpoint, prefix) = endpoints.bridge;
    let mut remote = connect_remote("bridge", endpoint, prefix, options.encoding, running)?;
    let (echo_endpoint, echo_prefix) = endpoints.echo;
    let mut zenoh = connect_remote(
        "Zenoh echo",
        echo_endpoint,
        echo_prefix,
        options.encoding,
        running,
    )?;
    wait_ready_both(&mut local, &mut remote, world, running)?;
    wait_ready(READY_WITHIN, Duration::from_millis(100), || {
        running()?;
        let echoed = zenoh
            .ask(ReferenceQuery::latest_gesture(), QUERY_TIMEOUT)
            .is_ok_and(|a| answered(&a));
        Ok(if echoed {
            Readiness::Ready(())
        } else {
            Readiness::Waiting("answer from the Zenoh echo".to_owned())
        })
    })?;

    let mut report = Report::default();
    let period = Duration::from_secs_f64(1.0 / options.rate);
    let end = Instant::now() + options.duration;
    let mut ids = human_ids(world);
    let mut ids_at = Instant::now();
    let mut tick = 0usize;
    while Instant::now() < end {
        let started = Instant::now();
        if ids_at.elapsed() >= Duration::from_millis(100) {
            ids = human_ids(world);
            ids_at = Instant::now();
        }
        let id = ids.get(tick % ids.len().max(1)).copied().unwrap_or(0);
        // Rotate which goes first, so that noise falls on all alike.
        for turn in 0..3 {
            let way = WAYS[(tick + turn) % WAYS.len()];
            let asked = Instant::now();
            let query = ReferenceQuery::human_object(id);
            let outcome = match way {
                Way::Bridge => Outcome::remote(remote.ask(query, QUERY_TIMEOUT)),
                Way::Zenoh => Outcome::remote(zenoh.ask(query, QUERY_TIMEOUT)),
                Way::Local => Outcome::local(local.ask(query, QUERY_TIMEOUT)),
            };
            report.tally(way, outcome, asked.elapsed());
        }
        tick += 1;
        if let Some(rest) = period.checked_sub(started.elapsed()) {
            std::thread::sleep(rest);
        }
    }
    Ok(report)
}

/// The three ways a tick asks.
#[derive(Debug, Clone, Copy)]
enum Way {
    Bridge,
    Zenoh,
    Local,
}

const WAYS: [Way; 3] = [Way::Bridge, Way::Zenoh, Way::Local];

/// What one question came to, whichever way it went.
enum Outcome {
    /// Answered from the solution (the round trip counts).
    Answered,
    Other,
    Timeout,
    Failed(AskError),
}

/// Why a question failed other than by going unanswered in time: counted
/// and logged, the run goes on.
#[derive(Debug, thiserror::Error)]
enum AskError {
    #[error(transparent)]
    Net(NetError),
    #[error(transparent)]
    Ipc(IpcError),
}

impl Outcome {
    fn remote(asked: Result<ReferenceAnswer, NetError>) -> Self {
        match asked {
            Ok(a) => Self::answer(&a),
            Err(NetError::NoReply { .. }) => Self::Timeout,
            Err(e) => Self::Failed(AskError::Net(e)),
        }
    }

    fn local(asked: Result<ReferenceAnswer, IpcError>) -> Self {
        match asked {
            Ok(a) => Self::answer(&a),
            Err(IpcError::Timeout { .. }) => Self::Timeout,
            Err(e) => Self::Failed(AskError::Ipc(e)),
        }
    }

    fn answer(a: &ReferenceAnswer) -> Self {
        if answered(a) {
            Self::Answered
        } else {
            Self::Other
        }
    }
}

/// The bridge may not listen yet: a client session fails at once when
/// nothing answers at the endpoint, so it is retried.
fn connect_remote(
    what: &str,
    endpoint: &str,
    prefix: &str,
    format: Format,
    running: &mut dyn FnMut() -> Result<(), LaunchError>,
) -> Result<RemoteClient, RunError> {
    let mut last = String::new();
    wait_ready(READY_WITHIN, Duration::from_millis(200), || {
        running()?;
        Ok(match RemoteClient::connect(endpoint, prefix, format) {
            Ok(client) => Readiness::Ready(client),
            Err(e) => {
                last = e.to_string();
                Readiness::Waiting(format!("session with the {what} at {endpoint}"))
            }
        })
    })
    .map_err(|source| RunError::Connect {
        what: what.to_owned(),
        endpoint: endpoint.to_owned(),
        last,
        source: Box::new(source),
    })
}

fn wait_ready_both(
    local: &mut ReferenceClient,
    remote: &mut RemoteClient,
    world: &LiveWorld,
    running: &mut dyn FnMut() -> Result<(), LaunchError>,
) -> Result<(), ReadyError> {
    let (mut local_ready, mut remote_ready) = (false, false);
    wait_ready(READY_WITHIN, Duration::from_millis(100), || {
        running()?;
        if let Some(&id) = human_ids(world).first() {
            local_ready = local_ready
                || local
                    .ask(ReferenceQuery::human_object(id), QUERY_TIMEOUT)
                    .is_ok_and(|a| answered(&a));
            remote_ready = remote_ready
                || remote
                    .ask(ReferenceQuery::human_object(id), QUERY_TIMEOUT)
                    .is_ok_and(|a| answered(&a));
        }
        Ok(match (local_ready, remote_ready) {
            (true, true) => Readiness::Ready(()),
            (false, false) => Readiness::Waiting("answer from the matcher".to_owned()),
            (true, false) => Readiness::Waiting("answer through the bridge".to_owned()),
            (false, true) => Readiness::Waiting("answer over iceoryx2".to_owned()),
        })
    })
}

impl Report {
    fn tally(&mut self, way: Way, outcome: Outcome, took: Duration) {
        match outcome {
            Outcome::Answered => match way {
                Way::Bridge => self.remote.push(took),
                Way::Zenoh => self.zenoh.push(took),
                Way::Local => self.local.push(took),
            },
            Outcome::Other => self.other += 1,
            Outcome::Timeout => self.timeouts += 1,
            Outcome::Failed(e) => {
                self.errors += 1;
                tracing::warn!("{way:?} query: {e}");
            }
        }
    }

    fn added(&self, q: f64) -> Option<f64> {
        difference(&self.remote, &self.local, q)
    }

    pub fn json(&self, options: &RemoteBenchOptions) -> serde_json::Value {
        let p = |s: &Samples, q| us(s.percentile(q));
        serde_json::json!({
            "remote_p50_us": p(&self.remote, 0.5),
            "remote_p99_us": p(&self.remote, 0.99),
            "local_p50_us": p(&self.local, 0.5),
            "local_p99_us": p(&self.local, 0.99),
            "added_p50_us": us(self.added(0.5)),
            "added_p99_us": us(self.added(0.99)),
            "zenoh_p50_us": p(&self.zenoh, 0.5),
            "zenoh_p99_us": p(&self.zenoh, 0.99),
            "bridge_over_zenoh_p50_us": us(difference(&self.remote, &self.zenoh, 0.5)),
            "bridge_over_zenoh_p99_us": us(difference(&self.remote, &self.zenoh, 0.99)),
            "remote_p999_us": p(&self.remote, 0.999),
            "local_p999_us": p(&self.local, 0.999),
            "zenoh_p999_us": p(&self.zenoh, 0.999),
            "remote_count": self.remote.count(),
            "local_count": self.local.count(),
            "zenoh_count": self.zenoh.count(),
            "other_count": self.other,
            "timeouts": self.timeouts,
            "errors": self.errors,
            "encoding": options.encoding.name(),
            "objects": options.objects,
            "rate_hz": options.rate,
            "duration_s": options.duration.as_secs_f64(),
        })
    }

    pub fn table(&self, options: &RemoteBenchOptions) -> String {
        let mut table = Table::new(&ROW_HEADER);
        let cell = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.1}"));
        for (name, s) in [
            ("remote (Zenoh, bridge)", &self.remote),
            ("local (iceoryx2)", &self.local),
            ("bare Zenoh (echo, no matcher)", &self.zenoh),
        ] {
            table.row(s.row(name));
        }
        format!(
            "{} objects, {} encoding, {} ticks/s for {:?}\n{table}the bridge adds: p50 {} us, \
             p99 {} us (bare Zenoh's round trip: p50 {} us, p99 {} us)\nother answers {}, timeouts {}, errors {}\n",
            options.objects,
            options.encoding.name(),
            options.rate,
            options.duration,
            cell(self.added(0.5)),
            cell(self.added(0.99)),
            cell(self.zenoh.percentile(0.5)),
            cell(self.zenoh.percentile(0.99)),
            self.other,
            self.timeouts,
            self.errors,
        )
    }
}

/// `a`'s percentile `q` less `b`'s.
fn difference(a: &Samples, b: &Samples, q: f64) -> Option<f64> {
    match (a.percentile(q), b.percentile(q)) {
        (Some(x), Some(y)) => Some(x - y),
        _ => None,
    }
}
