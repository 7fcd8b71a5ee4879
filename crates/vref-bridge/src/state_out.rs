//! State out: the robot camera's snapshots, the matcher's statistics and
//! its decision, read from iceoryx2 and published on Zenoh at most
//! `[bridge] state_rate_hz` times a second each (only what is new since
//! the last tick). Snapshots are validated first, like everything read
//! from shared memory: a monitor never sees what the matcher would refuse.

use std::sync::Arc;
use std::time::{Duration, Instant};

use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use vref_scene::{Limits, Side};
use vref_wire::ipc::{DecisionReader, StatsReader, create_node, drain, open_snapshot};
use vref_wire::{ObjectEntry, SnapshotHeader, WireError, validate_snapshot};
use zenoh::Wait;
use zenoh::pubsub::Publisher;

use crate::error::zenoh_err;
use crate::format::{Format, Message};
use crate::shared::{POLL, Shared, lock};
use crate::stats::Published;
use crate::workers::Worker;
use crate::{BridgeError, binary, json};

type SnapshotSubscriber = Subscriber<ipc::Service, [ObjectEntry], SnapshotHeader>;

/// Declares the three publishers and starts the thread that feeds them.
pub(crate) fn start(session: &zenoh::Session, shared: &Arc<Shared>) -> Result<Worker, BridgeError> {
    let format = Format::from(shared.config.bridge.state_encoding);
    let keys = &shared.keys;
    let declare = |key: String, message: Message| {
        session
            .declare_publisher(key.clone())
            .encoding(message.encoding(format))
            .wait()
            .map_err(|e| zenoh_err(format!("declaring {key}"), e))
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
        .map_err(|source| BridgeError::Spawn {
            name: "state",
            source,
        })
}

struct Publishers {
    snapshot: Publisher<'static>,
    stats: Publisher<'static>,
    decision: Publisher<'static>,
    format: Format,
}

fn run(shared: &Shared, out: &Publishers) -> Result<(), BridgeError> {
    let ipc = &shared.config.ipc;
    let pid = std::process::id();
    let node = create_node(ipc, "vref-bridge-state")?;
    let (robot, _) = open_snapshot(&node, ipc, Side::Robot)?;
    let robot: SnapshotSubscriber =
        robot
            .subscriber_builder()
            .create()
            .map_err(|e| BridgeError::Port {
                what: "robot snapshot subscriber",
                detail: format!("{e:?}"),
            })?;
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
    limits: &Limits,
    format: Format,
    last: &mut Option<(u64, u64)>,
) -> Option<Vec<u8>> {
    let drained = drain::newest(robot);
    if let Some(e) = &drained.error {
        tracing::warn!("receiving a robot snapshot: {e:?}");
    }
    let sample = drained.newest?;
    match encode_if_new(sample.user_header(), sample.payload(), limits, format, last) {
        Newest::Seen => None,
        Newest::Invalid(e) => {
            lock(&shared.published).invalid_local += 1;
            tracing::debug!("not publishing an invalid robot snapshot: {e}");
            None
        }
        Newest::New(bytes) => Some(bytes),
    }
}

/// What becomes of the newest robot snapshot read.
#[derive(Debug, PartialEq)]
enum Newest {
    /// Published already (the same session and sequence).
    Seen,
    /// Refused by validation, as the matcher would refuse it.
    Invalid(WireError),
    /// Encoded for the network.
    New(Vec<u8>),
}

/// `header` and `entries` encoded in `format` unless they are the
/// snapshot published `last` or invalid; `last` follows what was encoded.
fn encode_if_new(
    header: &SnapshotHeader,
    entries: &[ObjectEntry],
    limits: &Limits,
    format: Format,
    last: &mut Option<(u64, u64)>,
) -> Newest {
    let key = (header.session, header.sequence);
    if *last == Some(key) {
        return Newest::Seen;
    }
    if let Err(e) = validate_snapshot(header, entries, Side::Robot, limits) {
        return Newest::Invalid(e);
    }
    *last = Some(key);
    // Validation showed the count fits the slice.
    let used = entries
        .get(..header.object_count as usize)
        .unwrap_or(entries);
    Newest::New(match format {
        Format::Json => json::encode_snapshot(header, used),
        Format::Binary => binary::encode_snapshot(header, used),
    })
}

fn put(
    shared: &Shared,
    publisher: &Publisher<'static>,
    bytes: Vec<u8>,
    count: impl FnOnce(&mut Published),
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

#[cfg(test)]
mod tests {
    use vref_wire::{FRAME_NAME_LEN, MAX_FEATURE_DIM, SCHEMA_VERSION, SideCode};

    use super::*;

    fn entry(id: u64) -> ObjectEntry {
        let mut feature = [0.0; MAX_FEATURE_DIM];
        feature[..3].copy_from_slice(&[1.0, id as f32, 0.5]);
        ObjectEntry {
            track_id: id,
            position: [0.1 * id as f32, 0.2, 1.5],
            position_sigma: [0.01; 3],
            feature,
        }
    }

    fn header(session: u64, sequence: u64, count: u32) -> SnapshotHeader {
        let mut frame_name = [0; FRAME_NAME_LEN];
        frame_name[..5].copy_from_slice(b"robot");
        SnapshotHeader {
            session,
            sequence,
            timestamp_ns: 1,
            schema_version: SCHEMA_VERSION,
            side: SideCode::Robot as u32,
            object_count: count,
            feature_dim: 3,
            frame_name,
            up: [0.0; 3],
            flags: 0,
        }
    }

    #[test]
    fn a_snapshot_is_published_once() {
        let limits = Limits::default();
        let entries = [entry(1), entry(2)];
        let mut last = None;
        let first = encode_if_new(&header(5, 1, 2), &entries, &limits, Format::Json, &mut last);
        assert!(matches!(first, Newest::New(_)), "{first:?}");
        assert_eq!(last, Some((5, 1)));
        let again = encode_if_new(&header(5, 1, 2), &entries, &limits, Format::Json, &mut last);
        assert_eq!(again, Newest::Seen);
        let next = encode_if_new(&header(5, 2, 2), &entries, &limits, Format::Json, &mut last);
        assert!(matches!(next, Newest::New(_)), "{next:?}");
        // A new session with a sequence seen in the old one is new.
        let other = encode_if_new(&header(6, 2, 2), &entries, &limits, Format::Json, &mut last);
        assert!(matches!(other, Newest::New(_)), "{other:?}");
    }

    #[test]
    fn only_the_counted_objects_are_encoded() {
        let limits = Limits::default();
        // A slice longer than the count, as a loaned sample may be.
        let entries = [entry(1), entry(2), entry(3)];
        let header = header(5, 1, 2);
        let mut last = None;
        let Newest::New(bytes) =
            encode_if_new(&header, &entries, &limits, Format::Binary, &mut last)
        else {
            panic!("not encoded");
        };
        let (back, objects) = binary::decode_snapshot(&bytes).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(back, header);
        assert_eq!(objects, entries[..2]);
    }

    #[test]
    fn an_invalid_snapshot_is_refused_and_not_remembered() {
        let limits = Limits::default();
        let mut bad = [entry(1), entry(2)];
        bad[1].position[0] = f32::NAN;
        let mut last = None;
        let refused = encode_if_new(&header(5, 1, 2), &bad, &limits, Format::Json, &mut last);
        assert!(matches!(refused, Newest::Invalid(_)), "{refused:?}");
        assert_eq!(last, None);
        // A human snapshot on the robot's service is refused too.
        let mut human = header(5, 2, 2);
        human.side = SideCode::Human as u32;
        let good = [entry(1), entry(2)];
        let wrong_side = encode_if_new(&human, &good, &limits, Format::Json, &mut last);
        assert!(matches!(wrong_side, Newest::Invalid(_)), "{wrong_side:?}");
    }
}
