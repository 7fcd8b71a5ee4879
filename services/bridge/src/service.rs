//! The bridge's threads and what they share. iceoryx2 ports stay on the
//! thread that made them; Zenoh calls back on its own threads, so what
//! those callbacks touch (the intake and the counters) sits behind
//! mutexes held only for a check or an increment.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{Context, anyhow};
use vref_bridge::{
    BridgeStats, HeadsetIntake, IntakeLimits, Keys, NetError, Published, QueryIntake, new_session,
    open_bridge_session,
};
use vref_config::Config;
use vref_wire::ipc::{create_node, nap, now_ns};
use zenoh::Wait;

/// How often the bridge publishes its counters on Zenoh.
const STATS_EVERY: Duration = Duration::from_secs(1);
/// How often it logs them.
const REPORT_EVERY: Duration = Duration::from_secs(10);
/// A thread of the bridge; it ends with the reason it stopped.
pub type Worker = JoinHandle<anyhow::Result<()>>;

/// Longest a thread waits before looking at the stop flag again.
pub const POLL: Duration = Duration::from_millis(100);

/// Why the bridge stopped other than on a signal.
#[derive(Debug)]
pub enum Failure {
    /// The configuration cannot be used (exit code 2).
    Config(anyhow::Error),
    /// Something failed while running (exit code 1).
    Run(anyhow::Error),
}

impl From<anyhow::Error> for Failure {
    fn from(e: anyhow::Error) -> Self {
        Failure::Run(e)
    }
}

/// What the threads share.
pub struct Shared {
    pub config: Config,
    pub keys: Keys,
    pub stop: AtomicBool,
    pub intake: Mutex<HeadsetIntake>,
    pub queries: Mutex<QueryIntake>,
    pub published: Mutex<Published>,
}

impl Shared {
    pub fn stopping(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// A mutex's value even if a thread panicked holding it: counters and
/// checks stay usable (they hold no invariant a panic could break half-way).
pub fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Runs until SIGINT or SIGTERM.
pub fn run(config: &Config) -> Result<(), Failure> {
    let settings = &config.bridge;
    let keys = Keys::new(&settings.prefix).map_err(|e| Failure::Config(e.into()))?;
    let started_ns = now_ns();
    let session_id = new_session(started_ns, std::process::id());
    let limits = IntakeLimits {
        scene: config.scene.limits(),
        max_message_bytes: settings.max_message_bytes,
        max_snapshot_rate_hz: settings.max_snapshot_rate_hz,
        max_gesture_rate_hz: settings.max_gesture_rate_hz,
        session_takeover: Duration::from_millis(settings.session_takeover_ms),
    };
    let shared = Arc::new(Shared {
        config: config.clone(),
        keys: keys.clone(),
        stop: AtomicBool::new(false),
        intake: Mutex::new(HeadsetIntake::new(limits, session_id)),
        queries: Mutex::new(QueryIntake::new(
            settings.max_message_bytes,
            settings.max_query_rate_hz,
        )),
        published: Mutex::new(Published::default()),
    });

    // The node that hears SIGINT and SIGTERM; the threads make their own.
    let node = create_node(&config.ipc, "vref-bridge").context("creating the iceoryx2 node")?;
    node.try_cleanup_dead_nodes();
    let session = open_bridge_session(settings).map_err(|e| match e {
        NetError::Config { .. } => Failure::Config(e.into()),
        other => Failure::Run(other.into()),
    })?;
    let stats_publisher = session
        .declare_publisher(keys.bridge_stats())
        .encoding(vref_bridge::format::JSON)
        .wait()
        .map_err(|e| anyhow!("declaring {}: {e}", keys.bridge_stats()))?;

    let mut threads: Vec<(&str, Worker)> = Vec::new();
    // Subscribers whose callbacks feed the headset thread: kept alive here.
    let mut _subscribers = Vec::new();
    if settings.headset_in {
        let (subscribers, thread) = crate::headset::start(&session, &shared)?;
        _subscribers = subscribers;
        threads.push(("headset", thread));
    }
    if settings.queries_in {
        threads.push(("queries", crate::queries::start(&session, &shared)?));
    }
    if settings.state_out {
        threads.push(("state", crate::state::start(&session, &shared)?));
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

    let stats = |taken_ns| {
        // One lock at a time: each guard is dropped before the next is taken.
        let (human_snapshot, human_gesture) = {
            let intake = lock(&shared.intake);
            (
                intake.snapshot_counters().clone(),
                intake.ray_counters().clone(),
            )
        };
        let reference = lock(&shared.queries).counters().clone();
        let published = lock(&shared.published).clone();
        BridgeStats {
            started_ns,
            taken_ns,
            pid: std::process::id(),
            prefix: keys.prefix().to_owned(),
            session: session_id,
            human_snapshot,
            human_gesture,
            reference,
            published,
        }
    };
    let mut last_stats = Instant::now();
    let mut last_report = Instant::now();
    let mut failure = None;
    while nap(&node, POLL) {
        if let Some((name, _)) = threads.iter().find(|(_, t)| t.is_finished()) {
            failure = Some(anyhow!("the {name} thread stopped"));
            break;
        }
        if last_stats.elapsed() >= STATS_EVERY {
            last_stats = Instant::now();
            if let Err(e) = stats_publisher.put(stats(now_ns()).to_json()).wait() {
                tracing::warn!("publishing the bridge's statistics: {e}");
            }
        }
        if last_report.elapsed() >= REPORT_EVERY {
            last_report = Instant::now();
            report(&stats(now_ns()));
        }
    }
    shared.stop.store(true, Ordering::Relaxed);
    for (name, thread) in threads {
        match thread.join() {
            Ok(Ok(())) => {}
            Ok(Err(e)) => {
                let e = e.context(format!("the {name} thread"));
                tracing::error!("{e:#}");
                failure.get_or_insert(e);
            }
            Err(_) => {
                failure.get_or_insert(anyhow!("the {name} thread panicked"));
            }
        }
    }
    let last = stats(now_ns());
    report(&last);
    drop(_subscribers);
    drop(stats_publisher);
    session
        .close()
        .wait()
        .map_err(|e| Failure::Run(anyhow!("closing the Zenoh session: {e}")))?;
    tracing::info!("bridge stopped");
    match failure {
        Some(e) => Err(Failure::Run(e)),
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
