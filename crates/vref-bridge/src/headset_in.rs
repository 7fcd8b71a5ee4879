//! Headset in: Zenoh subscribers on `<prefix>/human/snapshot` and
//! `<prefix>/human/gesture` check each message in their callback (the
//! intake), and what passes is published into the local iceoryx2 services
//! by one thread, as the gesture feed would.

use std::sync::Arc;
use std::sync::mpsc::{Receiver, RecvTimeoutError, SyncSender, TrySendError, sync_channel};
use std::time::Instant;

use vref_scene::Side;
use vref_wire::ipc::{GesturePublisher, SnapshotPublisher, create_node, now_ns};
use vref_wire::{ObjectEntry, PointingRay, SnapshotHeader};
use zenoh::Wait;
use zenoh::pubsub::Subscriber;
use zenoh::sample::Sample;

use crate::BridgeError;
use crate::error::zenoh_err;
use crate::shared::{POLL, Shared, lock};
use crate::workers::Worker;

/// Messages checked and waiting to be published. Small: the intake has
/// already cut the traffic to the configured rates, so a full queue means
/// the publishing side is stuck, and newer messages are worth more.
const QUEUE: usize = 8;

/// A message that passed the intake.
enum Inbound {
    Snapshot(SnapshotHeader, Vec<ObjectEntry>),
    Ray(PointingRay),
}

/// Declares the two subscribers and starts the publishing thread.
pub(crate) fn start(
    session: &zenoh::Session,
    shared: &Arc<Shared>,
) -> Result<(Vec<Subscriber<()>>, Worker), BridgeError> {
    let (tx, rx) = sync_channel::<Inbound>(QUEUE);
    let keys = &shared.keys;
    let snapshots = {
        let (shared, tx) = (Arc::clone(shared), tx.clone());
        session
            .declare_subscriber(keys.human_snapshot())
            .callback(move |sample| on_snapshot(&shared, &tx, &sample))
            .wait()
            .map_err(|e| zenoh_err(format!("subscribing to {}", keys.human_snapshot()), e))?
    };
    let rays = {
        let shared = Arc::clone(shared);
        session
            .declare_subscriber(keys.human_gesture())
            .callback(move |sample| on_ray(&shared, &tx, &sample))
            .wait()
            .map_err(|e| zenoh_err(format!("subscribing to {}", keys.human_gesture()), e))?
    };
    let shared = Arc::clone(shared);
    let thread = std::thread::Builder::new()
        .name("headset-in".to_owned())
        .spawn(move || publish(&shared, &rx))
        .map_err(|source| BridgeError::Spawn {
            name: "headset",
            source,
        })?;
    Ok((vec![snapshots, rays], thread))
}

fn on_snapshot(shared: &Shared, tx: &SyncSender<Inbound>, sample: &Sample) {
    let encoding = sample.encoding().to_string();
    let payload = sample.payload().to_bytes();
    let mut intake = lock(&shared.intake);
    match intake.snapshot(&encoding, &payload, Instant::now(), now_ns()) {
        Ok((header, entries)) => {
            if let Err(e) = tx.try_send(Inbound::Snapshot(header, entries)) {
                intake.snapshot_counters_mut().refuse(queue_refusal(&e));
            }
        }
        Err(refusal) => tracing::debug!(reason = refusal.name(), "refused snapshot: {refusal}"),
    }
}

fn on_ray(shared: &Shared, tx: &SyncSender<Inbound>, sample: &Sample) {
    let encoding = sample.encoding().to_string();
    let payload = sample.payload().to_bytes();
    let mut intake = lock(&shared.intake);
    match intake.ray(&encoding, &payload, Instant::now(), now_ns()) {
        Ok(ray) => {
            if let Err(e) = tx.try_send(Inbound::Ray(ray)) {
                intake.ray_counters_mut().refuse(queue_refusal(&e));
            }
        }
        Err(refusal) => tracing::debug!(reason = refusal.name(), "refused ray: {refusal}"),
    }
}

/// The counter a message that passed but could not be queued goes to.
fn queue_refusal<T>(e: &TrySendError<T>) -> &'static str {
    match e {
        TrySendError::Full(_) => "busy",
        TrySendError::Disconnected(_) => "stopped",
    }
}

/// Publishes what passed into iceoryx2 until the bridge stops.
fn publish(shared: &Shared, rx: &Receiver<Inbound>) -> Result<(), BridgeError> {
    let ipc = &shared.config.ipc;
    let node = create_node(ipc, "vref-bridge-headset")?;
    // Declared after the node, so dropped before it. The frame name given
    // here is unused: each snapshot carries the headset's own.
    let mut snapshots = SnapshotPublisher::new(&node, ipc, Side::Human, "headset")?;
    let mut rays = GesturePublisher::new(&node, ipc)?;
    while !shared.stopping() {
        let inbound = match rx.recv_timeout(POLL) {
            Ok(inbound) => inbound,
            Err(RecvTimeoutError::Timeout) => continue,
            Err(RecvTimeoutError::Disconnected) => break,
        };
        let mut published = lock(&shared.published);
        let failed = match inbound {
            Inbound::Snapshot(header, entries) => match snapshots.publish_raw(header, &entries) {
                Ok(()) => {
                    published.human_snapshot += 1;
                    None
                }
                Err(e) => Some(("snapshot", e)),
            },
            Inbound::Ray(ray) => match rays.publish_raw(ray) {
                Ok(()) => {
                    published.human_gesture += 1;
                    None
                }
                Err(e) => Some(("ray", e)),
            },
        };
        if let Some((what, e)) = failed {
            published.failed += 1;
            tracing::warn!("publishing a headset {what}: {e}");
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_queue_is_busy_and_a_closed_one_stopped() {
        let (tx, rx) = sync_channel::<u8>(1);
        assert!(tx.try_send(1).is_ok());
        let full = tx.try_send(2).err();
        assert_eq!(full.as_ref().map(queue_refusal), Some("busy"));
        drop(rx);
        let closed = tx.try_send(3).err();
        assert_eq!(closed.as_ref().map(queue_refusal), Some("stopped"));
    }
}
