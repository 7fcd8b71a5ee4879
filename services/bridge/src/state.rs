//! State out: the robot camera's snapshots, the matcher's statistics and
//! its decision, read from iceoryx2 and published on Zenoh at most
//! `[bridge] state_rate_hz` times a second each (only what is new since
//! the last tick). Snapshots are validated first, like everything read
//! from shared memory: a monitor never sees what the matcher would refuse.

use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{Context, anyhow};
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use vref_bridge::{Format, Message, binary, json};
use vref_config::StateEncoding;
use vref_scene::Side;
use vref_wire::ipc::{DecisionReader, StatsReader, create_node, open_snapshot};
use vref_wire::{ObjectEntry, SnapshotHeader, validate_snapshot};
use zenoh::Wait;
use zenoh::pubsub::Publisher;

use crate::service::{POLL, Shared, Worker, lock};

type SnapshotSubscriber = Subscriber<ipc::Service, [ObjectEntry], SnapshotHeader>;

pub fn start(session: &zenoh::Session, shared: &Arc<Shared>) -> anyhow::Result<Worker> {
    let format = match shared.config.bridge.state_encoding {
        StateEncoding::Json => Format::Json,
        StateEncoding::Binary => Format::Binary,
    };
    let keys = &shared.keys;
    let declare = |key: String, message: Message| {
        session
            .declare_publisher(key.clone())
            .encoding(message.encoding(format))
            .wait()
            .map_err(|e| anyhow!("declaring {key}: {e}"))
    };
    let publishers = Publishers {
        snapshot: declare(keys.robot_snapshot(), Message::Snapshot)?,
        stats: declare(keys.matcher_stats(), Message::Stats)?,
        decision: declare(keys.matcher_decision(), Message::Decision)?,
        format,
    };
    let shared = Arc::clone(shared);
    std::thread::Builder::new()
        .name("state-out".to_owned())
        .spawn(move || run(&shared, &publishers))
        .context("starting the state thread")
}

struct Publishers {
    snapshot: Publisher<'static>,
    stats: Publisher<'static>,
    decision: Publisher<'static>,
    format: Format,
}

fn run(shared: &Shared, out: &Publishers) -> anyhow::Result<()> {
    let ipc = &shared.config.ipc;
    let pid = std::process::id();
    let node = create_node(ipc, "vref-bridge-state")?;
    let (robot, _) = open_snapshot(&node, ipc, Side::Robot)?;
    let robot: SnapshotSubscriber = robot
        .subscriber_builder()
        .create()
        .map_err(|e| anyhow!("creating the robot snapshot subscriber: {e:?}"))?;
    let stats = StatsReader::connect(ipc, &format!("vref-bridge-stats-{pid}"))?;
    let decisions = DecisionReader::connect(ipc, &format!("vref-bridge-decision-{pid}"))?;
    let period = Duration::from_secs_f64(1.0 / shared.config.bridge.state_rate_hz);
    let limits = shared.config.scene.limits();
    let mut last_snapshot = None;
    while !shared.stopping() {
        let tick = Instant::now();
        if let Some(bytes) = robot_snapshot(shared, &robot, &limits, out.format, &mut last_snapshot)
        {
            put(shared, &out.snapshot, bytes, |p| p.robot_snapshot += 1);
        }
        match stats.latest() {
            Ok(Some(s)) => {
                let bytes = match out.format {
                    Format::Json => json::encode_stats(&s),
                    Format::Binary => binary::encode_stats(&s),
                };
                put(shared, &out.stats, bytes, |p| p.matcher_stats += 1);
            }
            Ok(None) => {}
            Err(e) => tracing::warn!("reading the matcher's statistics: {e}"),
        }
        match decisions.latest() {
            Ok(Some(Ok(d))) => {
                let bytes = match out.format {
                    Format::Json => json::encode_decision(&d.header, &d.entries),
                    Format::Binary => binary::encode_decision(&d.header, &d.entries),
                };
                put(shared, &out.decision, bytes, |p| p.matcher_decision += 1);
            }
            Ok(Some(Err(e))) => {
                lock(&shared.published).invalid_local += 1;
                tracing::warn!("refused a decision read from shared memory: {e}");
            }
            Ok(None) => {}
            Err(e) => tracing::warn!("reading the matcher's decision: {e}"),
        }
        // Slept in steps, so that a stop is noticed.
        while tick.elapsed() < period && !shared.stopping() {
            std::thread::sleep(period.saturating_sub(tick.elapsed()).min(POLL));
        }
    }
    Ok(())
}

/// The newest robot snapshot if it is new and valid, encoded.
fn robot_snapshot(
    shared: &Shared,
    robot: &SnapshotSubscriber,
    limits: &vref_scene::Limits,
    format: Format,
    last: &mut Option<(u64, u64)>,
) -> Option<Vec<u8>> {
    let mut latest = None;
    loop {
        match robot.receive() {
            Ok(Some(sample)) => latest = Some(sample),
            Ok(None) => break,
            Err(e) => {
                tracing::warn!("receiving a robot snapshot: {e:?}");
                break;
            }
        }
    }
    let sample = latest?;
    let (header, entries) = (sample.user_header(), sample.payload());
    let key = (header.session, header.sequence);
    if *last == Some(key) {
        return None;
    }
    if let Err(e) = validate_snapshot(header, entries, Side::Robot, limits) {
        lock(&shared.published).invalid_local += 1;
        tracing::debug!("not publishing an invalid robot snapshot: {e}");
        return None;
    }
    *last = Some(key);
    // Validation showed the count fits the slice.
    let used = entries.get(..header.object_count as usize)?;
    Some(match format {
        Format::Json => json::encode_snapshot(header, used),
        Format::Binary => binary::encode_snapshot(header, used),
    })
}

fn put(
    shared: &Shared,
    publisher: &Publisher<'static>,
    bytes: Vec<u8>,
    count: impl FnOnce(&mut vref_bridge::Published),
) {
    let sent = publisher.put(bytes).wait();
    let mut published = lock(&shared.published);
    match sent {
        Ok(()) => count(&mut published),
        Err(e) => {
            published.failed += 1;
            tracing::warn!("publishing on {}: {e}", publisher.key_expr());
        }
    }
}
