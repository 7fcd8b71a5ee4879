//! `vref bench remote`: what the network edge costs. One run starts the
//! matcher, both feeds and vref-bridge (on a loopback port of its own) and
//! asks the same questions two ways: over Zenoh through the bridge, as a
//! controller on another computer would, and over iceoryx2 to the matcher
//! directly. The difference of the two is what the bridge and Zenoh add.

use std::time::{Duration, Instant};

use anyhow::{Context, anyhow};
use vref_bridge::RemoteClient;
use vref_config::{BridgeSettings, Config, ZenohMode};
use vref_feed::synthetic_world;
use vref_sim::LiveWorld;
use vref_wire::ipc::ReferenceClient;
use vref_wire::{AnswerStatus, QueryKind, ReferenceAnswer, ReferenceQuery, SCHEMA_VERSION};

use crate::bench_query::{Samples, human_ids, us};
use crate::cli::BenchRemoteArgs;
use crate::failure::{Blame, Failure};
use crate::harness;
use crate::stdout;
use crate::table::Table;
use vref_harness::launch::{self, Isolation, Services, keep_logs_if, prepare};
use vref_harness::ready::{READY_WITHIN, Readiness, ReadyError, wait_ready};

/// One query's time limit.
const QUERY_TIMEOUT: Duration = Duration::from_secs(2);

pub fn remote(args: &BenchRemoteArgs) -> Result<(), Failure> {
    if args.objects < 2 {
        return Err(anyhow!("--objects: at least 2")).bad_input();
    }
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let (_, world) = synthetic_world(&config.feeds, Some(args.objects)).bad_input()?;
    let bin_dir = harness::bin_dir()?;
    let bridge_binary = launch::binary(&bin_dir, "vref-bridge").runtime()?;
    let endpoint = format!("tcp/127.0.0.1:{}", free_port().runtime()?);
    let prefix = format!("vref/bench{}", std::process::id());
    let mut config = config;
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
    let Isolation {
        binaries,
        dir,
        config: own,
        config_path,
    } = prepare(&config, &bin_dir, "bench-remote", "vbr").runtime()?;

    let feed_args = ["--objects".to_owned(), args.objects.to_string()];
    let mut system =
        Services::start_system(&binaries, &config_path, &feed_args, dir.path()).runtime()?;
    let mut command = std::process::Command::new(&bridge_binary);
    command.arg("--config").arg(&config_path);
    system.spawn("vref-bridge", command).runtime()?;
    let outcome = measure(args, &own, &world, &endpoint, &prefix, &mut || {
        system.ensure_running().map_err(anyhow::Error::from)
    });
    let stopped = system.stop();
    keep_logs_if(outcome.is_err() || stopped.is_err(), dir);
    let report = outcome.runtime()?;
    let text = if args.json {
        format!("{}\n", report.json(args))
    } else {
        report.table(args)
    };
    stdout::print(&text)?;
    stopped.runtime()
}

/// A loopback port free a moment ago, for the bridge to listen on.
fn free_port() -> anyhow::Result<u16> {
    let listener =
        std::net::TcpListener::bind("127.0.0.1:0").context("finding a free loopback port")?;
    Ok(listener.local_addr()?.port())
}

#[derive(Debug, Default)]
struct Report {
    remote: Samples,
    local: Samples,
    /// Answers that did not go through the solution (not ready, stale, ...).
    other: u64,
    timeouts: u64,
    errors: u64,
}

fn human_object(id: u64) -> ReferenceQuery {
    ReferenceQuery {
        request_id: 0,
        human_object_id: id,
        ray_origin: [0.0; 3],
        ray_direction: [0.0; 3],
        cone_half_angle: 0.0,
        kind: QueryKind::HumanObject as u32,
        schema_version: SCHEMA_VERSION,
        reserved: 0,
    }
}

fn answered(a: &ReferenceAnswer) -> bool {
    matches!(
        a.status(),
        AnswerStatus::Ok | AnswerStatus::Ambiguous | AnswerStatus::NoMatch
    )
}

fn measure(
    args: &BenchRemoteArgs,
    config: &Config,
    world: &LiveWorld,
    endpoint: &str,
    prefix: &str,
    running: &mut dyn FnMut() -> anyhow::Result<()>,
) -> anyhow::Result<Report> {
    let pid = std::process::id();
    let mut local = ReferenceClient::connect(&config.ipc, &format!("vref-bench-local-{pid}"))?;
    let mut remote = connect_remote(endpoint, prefix, args.encoding, running)?;
    wait_ready_both(&mut local, &mut remote, world, running)?;

    let mut report = Report::default();
    let period = Duration::from_secs_f64(1.0 / args.rate);
    let end = Instant::now() + args.duration;
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
        // Alternate which goes first, so that noise falls on both alike.
        let remote_first = tick.is_multiple_of(2);
        for remote_turn in [remote_first, !remote_first] {
            let asked = Instant::now();
            if remote_turn {
                match remote.ask(human_object(id), QUERY_TIMEOUT) {
                    Ok(a) if answered(&a) => report.remote.push(asked.elapsed()),
                    Ok(_) => report.other += 1,
                    Err(vref_bridge::NetError::NoReply { .. }) => report.timeouts += 1,
                    Err(e) => {
                        report.errors += 1;
                        tracing::warn!("remote query: {e}");
                    }
                }
            } else {
                match local.ask(human_object(id), QUERY_TIMEOUT) {
                    Ok(a) if answered(&a) => report.local.push(asked.elapsed()),
                    Ok(_) => report.other += 1,
                    Err(vref_wire::ipc::IpcError::Timeout { .. }) => report.timeouts += 1,
                    Err(e) => {
                        report.errors += 1;
                        tracing::warn!("local query: {e}");
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

/// The bridge may not listen yet: a client session fails at once when
/// nothing answers at the endpoint, so it is retried.
fn connect_remote(
    endpoint: &str,
    prefix: &str,
    format: vref_bridge::Format,
    running: &mut dyn FnMut() -> anyhow::Result<()>,
) -> anyhow::Result<RemoteClient> {
    let mut last = String::new();
    wait_ready(READY_WITHIN, Duration::from_millis(200), || {
        running().map_err(|e| ReadyError::Check(format!("{e:#}")))?;
        Ok(match RemoteClient::connect(endpoint, prefix, format) {
            Ok(client) => Readiness::Ready(client),
            Err(e) => {
                last = e.to_string();
                Readiness::Waiting(format!("session with the bridge at {endpoint}"))
            }
        })
    })
    .map_err(|e| anyhow!("connecting to the bridge at {endpoint}: {e} ({last})"))
}

fn wait_ready_both(
    local: &mut ReferenceClient,
    remote: &mut RemoteClient,
    world: &LiveWorld,
    running: &mut dyn FnMut() -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let (mut local_ready, mut remote_ready) = (false, false);
    wait_ready(READY_WITHIN, Duration::from_millis(100), || {
        running().map_err(|e| ReadyError::Check(format!("{e:#}")))?;
        if let Some(&id) = human_ids(world).first() {
            local_ready = local_ready
                || local
                    .ask(human_object(id), QUERY_TIMEOUT)
                    .is_ok_and(|a| answered(&a));
            remote_ready = remote_ready
                || remote
                    .ask(human_object(id), QUERY_TIMEOUT)
                    .is_ok_and(|a| answered(&a));
        }
        Ok(match (local_ready, remote_ready) {
            (true, true) => Readiness::Ready(()),
            (false, false) => Readiness::Waiting("answer from the matcher".to_owned()),
            (true, false) => Readiness::Waiting("answer through the bridge".to_owned()),
            (false, true) => Readiness::Waiting("answer over iceoryx2".to_owned()),
        })
    })
    .map_err(anyhow::Error::from)
}

impl Report {
    fn added(&self, q: f64) -> Option<f64> {
        match (self.remote.percentile(q), self.local.percentile(q)) {
            (Some(r), Some(l)) => Some(r - l),
            _ => None,
        }
    }

    fn json(&self, args: &BenchRemoteArgs) -> serde_json::Value {
        let p = |s: &Samples, q| us(s.percentile(q));
        serde_json::json!({
            "remote_p50_us": p(&self.remote, 0.5),
            "remote_p99_us": p(&self.remote, 0.99),
            "local_p50_us": p(&self.local, 0.5),
            "local_p99_us": p(&self.local, 0.99),
            "added_p50_us": us(self.added(0.5)),
            "added_p99_us": us(self.added(0.99)),
            "remote_p999_us": p(&self.remote, 0.999),
            "local_p999_us": p(&self.local, 0.999),
            "remote_count": self.remote.count(),
            "local_count": self.local.count(),
            "other_count": self.other,
            "timeouts": self.timeouts,
            "errors": self.errors,
            "encoding": args.encoding.name(),
            "objects": args.objects,
            "rate_hz": args.rate,
            "duration_s": args.duration.as_secs_f64(),
        })
    }

    fn table(&self, args: &BenchRemoteArgs) -> String {
        let mut table = Table::new(&vref_harness::samples::ROW_HEADER);
        let cell = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.1}"));
        for (name, s) in [
            ("remote (Zenoh, bridge)", &self.remote),
            ("local (iceoryx2)", &self.local),
        ] {
            table.row(s.row(name));
        }
        format!(
            "{} objects, {} encoding, {} ticks/s for {:?}\n{table}the bridge adds: p50 {} us, \
             p99 {} us\nother answers {}, timeouts {}, errors {}\n",
            args.objects,
            args.encoding.name(),
            args.rate,
            args.duration,
            cell(self.added(0.5)),
            cell(self.added(0.99)),
            self.other,
            self.timeouts,
            self.errors,
        )
    }
}
