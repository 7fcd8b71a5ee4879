//! The bridge's loop: it opens the Zenoh session, starts a thread for
//! each direction `[bridge]` turns on (headset in, queries in, state
//! out), publishes and logs its counters, and stops them all on SIGINT or
//! SIGTERM, or when one of them fails.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use vref_config::Config;
use vref_wire::ipc::{create_node, nap, now_ns};
use zenoh::Wait;

use crate::error::zenoh_err;
use crate::keys::Keys;
use crate::net::open_bridge_session;
use crate::shared::{POLL, Shared};
use crate::stats::BridgeStats;
use crate::workers::Workers;
use crate::{BridgeError, NetError, format, headset_in, new_session, queries_in, state_out};

/// How often the bridge publishes its counters on Zenoh.
const STATS_EVERY: Duration = Duration::from_secs(1);
/// How often it logs them.
const REPORT_EVERY: Duration = Duration::from_secs(10);

/// Runs until SIGINT or SIGTERM.
pub fn run(config: &Config) -> Result<(), BridgeError> {
    run_until(config, &AtomicBool::new(false))
}

/// Runs until SIGINT or SIGTERM, or until `stop` is set (within 100 ms):
/// a bridge inside another program, or a test's.
pub fn run_until(config: &Config, stop: &AtomicBool) -> Result<(), BridgeError> {
    let settings = &config.bridge;
    let keys = Keys::new(&settings.prefix).map_err(BridgeError::Config)?;
    let started_ns = now_ns();
    let session_id = new_session(started_ns, std::process::id());
    let shared = Arc::new(Shared::new(config, keys.clone(), session_id, started_ns));

    // The node that hears SIGINT and SIGTERM; the threads make their own.
    let node = create_node(&config.ipc, "vref-bridge").map_err(BridgeError::Node)?;
    node.try_cleanup_dead_nodes();
    let session = open_bridge_session(settings).map_err(|e| match e {
        NetError::Config { .. } => BridgeError::Config(e),
        other => BridgeError::Net(other),
    })?;
    let stats_publisher = session
        .declare_publisher(keys.bridge_stats())
        .encoding(format::JSON)
        .wait()
        .map_err(|e| zenoh_err(format!("declaring {}", keys.bridge_stats()), e))?;

    let mut workers = Workers::default();
    // Subscribers whose callbacks feed the headset thread: kept alive here.
    let mut _subscribers = Vec::new();
    if settings.headset_in {
        let (subscribers, thread) = headset_in::start(&session, &shared)?;
        _subscribers = subscribers;
        workers.push("headset", thread);
    }
    if settings.queries_in {
        workers.push("queries", queries_in::start(&session, &shared)?);
    }
    if settings.state_out {
        workers.push("state", state_out::start(&session, &shared)?);
    }
    tracing::info!(
        prefix = %keys.prefix(),
        mode = settings.mode.name(),
        listen = ?settings.listen,
        connect = ?settings.connect,
        headset_in = settings.headset_in,
        queries_in = settings.queries_in,
        state_out = settings.state_out,
        session = session_id,
        "bridge ready"
    );

    let mut last_stats = Instant::now();
    let mut last_report = Instant::now();
    let mut failure = None;
    while nap(&node, POLL) && !stop.load(Ordering::Relaxed) {
        if let Some(ended) = workers.ended() {
            failure = Some(ended);
            break;
        }
        if last_stats.elapsed() >= STATS_EVERY {
            last_stats = Instant::now();
            if let Err(e) = stats_publisher.put(shared.stats(now_ns()).to_json()).wait() {
                tracing::warn!("publishing the bridge's statistics: {e}");
            }
        }
        if last_report.elapsed() >= REPORT_EVERY {
            last_report = Instant::now();
            report(&shared.stats(now_ns()));
        }
    }
    shared.stop();
    let failure = failure.or(workers.join());
    report(&shared.stats(now_ns()));
    drop(_subscribers);
    drop(stats_publisher);
    session
        .close()
        .wait()
        .map_err(|e| zenoh_err("closing the Zenoh session", e))?;
    tracing::info!("bridge stopped");
    match failure {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

fn report(stats: &BridgeStats) {
    for (name, c) in [
        ("human/snapshot", &stats.human_snapshot),
        ("human/gesture", &stats.human_gesture),
        ("reference", &stats.reference),
    ] {
        if c.received > 0 {
            tracing::info!(
                stream = name,
                received = c.received,
                passed = c.passed,
                refused = ?c.refused,
                "network in"
            );
        }
    }
    tracing::info!(published = ?stats.published, "published");
}

#[cfg(test)]
mod tests {
    use super::*;
    use vref_logging::exit::Fault;

    #[test]
    fn a_bad_prefix_is_a_configuration_error_before_anything_opens() {
        let mut config = Config::default();
        config.bridge.prefix = "vref/*".to_owned();
        let e = run_until(&config, &AtomicBool::new(true));
        assert!(
            matches!(&e, Err(BridgeError::Config(NetError::Prefix { .. }))),
            "{e:?}"
        );
        assert!(e.is_err_and(|e| e.is_bad_input()));
    }
}
