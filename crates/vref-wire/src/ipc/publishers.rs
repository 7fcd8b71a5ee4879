use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::prelude::*;
use vref_scene::Side;

use super::error::{IpcError, iceoryx_err};
use super::{IpcSettings, Node, now_ns, open_gesture, open_snapshot, slice_publisher_qos};
use crate::{FRAME_NAME_LEN, ObjectEntry, PointingRay, SCHEMA_VERSION, SideCode, SnapshotHeader};

/// Publishes one side's snapshots, written in place into loaned shared
/// memory, and wakes the subscribers.
pub struct SnapshotPublisher {
    side: Side,
    frame_name: [u8; FRAME_NAME_LEN],
    session: u64,
    sequence: u64,
    publisher: Publisher<ipc::Service, [ObjectEntry], SnapshotHeader>,
    notifier: Notifier<ipc::Service>,
}

impl std::fmt::Debug for SnapshotPublisher {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SnapshotPublisher")
            .field("side", &self.side)
            .field("sequence", &self.sequence)
            .finish_non_exhaustive()
    }
}

impl SnapshotPublisher {
    /// `frame_name` is truncated to the wire's 32 bytes.
    pub fn new(
        node: &Node,
        settings: &IpcSettings,
        side: Side,
        frame_name: &str,
    ) -> Result<Self, IpcError> {
        let qos = slice_publisher_qos(settings);
        let (data, event) = open_snapshot(node, settings, side)?;
        let publisher = data
            .publisher_builder()
            .initial_max_slice_len(qos.initial_max_slice_len)
            .allocation_strategy(qos.allocation_strategy)
            .create()
            .map_err(|e| iceoryx_err("creating snapshot publisher", e))?;
        let notifier = event
            .notifier_builder()
            .create()
            .map_err(|e| iceoryx_err("creating snapshot notifier", e))?;
        let mut name = [0u8; FRAME_NAME_LEN];
        let bytes = frame_name.as_bytes();
        let len = bytes.len().min(FRAME_NAME_LEN);
        name[..len].copy_from_slice(&bytes[..len]);
        Ok(Self {
            side,
            frame_name: name,
            session: new_session(),
            sequence: 0,
            publisher,
            notifier,
        })
    }

    /// Publishes `count` objects, the i-th written by `object(i)` straight
    /// into shared memory, with `feature_dim` used feature entries and the
    /// view's up vector if known ([`crate::wire_up`] of the graph
    /// published). Returns the snapshot's sequence number.
    pub fn publish(
        &mut self,
        count: usize,
        feature_dim: usize,
        up: Option<[f32; 3]>,
        timestamp_ns: u64,
        object: impl FnMut(usize) -> ObjectEntry,
    ) -> Result<u64, IpcError> {
        self.sequence += 1;
        let mut header = self.header(count, feature_dim, timestamp_ns);
        header.set_up(up);
        self.send(header, count, object)?;
        Ok(self.sequence)
    }

    /// Publishes a header and entries exactly as given, for tools that
    /// must write what a faulty publisher would (the header is not
    /// derived from the entries).
    pub fn publish_raw(
        &mut self,
        header: SnapshotHeader,
        entries: &[ObjectEntry],
    ) -> Result<(), IpcError> {
        self.send(header, entries.len(), |i| entries[i])
    }

    /// Loans `count` entries, writes `header` and `object(i)` in place,
    /// sends and wakes the subscribers.
    fn send(
        &mut self,
        header: SnapshotHeader,
        count: usize,
        object: impl FnMut(usize) -> ObjectEntry,
    ) -> Result<(), IpcError> {
        let mut sample = self
            .publisher
            .loan_slice_uninit(count)
            .map_err(|e| iceoryx_err("loaning a snapshot", e))?;
        *sample.user_header_mut() = header;
        sample
            .write_from_fn(object)
            .send()
            .map_err(|e| iceoryx_err("sending a snapshot", e))?;
        self.notifier
            .notify()
            .map_err(|e| iceoryx_err("notifying a snapshot", e))?;
        Ok(())
    }

    fn header(&self, count: usize, feature_dim: usize, timestamp_ns: u64) -> SnapshotHeader {
        SnapshotHeader {
            session: self.session,
            sequence: self.sequence,
            timestamp_ns,
            schema_version: SCHEMA_VERSION,
            side: match self.side {
                Side::Robot => SideCode::Robot as u32,
                Side::Human => SideCode::Human as u32,
            },
            object_count: u32::try_from(count).unwrap_or(u32::MAX),
            feature_dim: u32::try_from(feature_dim).unwrap_or(u32::MAX),
            frame_name: self.frame_name,
            up: [0.0; 3],
            flags: 0,
        }
    }
}

/// Publishes pointing rays.
pub struct GesturePublisher {
    session: u64,
    sequence: u64,
    publisher: Publisher<ipc::Service, PointingRay, ()>,
    notifier: Notifier<ipc::Service>,
}

impl std::fmt::Debug for GesturePublisher {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GesturePublisher")
            .field("sequence", &self.sequence)
            .finish_non_exhaustive()
    }
}

impl GesturePublisher {
    pub fn new(node: &Node, settings: &IpcSettings) -> Result<Self, IpcError> {
        let (data, event) = open_gesture(node, settings)?;
        let publisher = data
            .publisher_builder()
            .create()
            .map_err(|e| iceoryx_err("creating gesture publisher", e))?;
        let notifier = event
            .notifier_builder()
            .create()
            .map_err(|e| iceoryx_err("creating gesture notifier", e))?;
        Ok(Self {
            session: new_session(),
            sequence: 0,
            publisher,
            notifier,
        })
    }

    /// Publishes a ray; sequence, timestamp and schema version are filled
    /// in. Returns the sequence number.
    pub fn publish(
        &mut self,
        origin: [f32; 3],
        direction: [f32; 3],
        cone_half_angle: f32,
        confidence: f32,
    ) -> Result<u64, IpcError> {
        self.sequence += 1;
        let ray = PointingRay {
            session: self.session,
            sequence: self.sequence,
            timestamp_ns: now_ns(),
            origin,
            direction,
            cone_half_angle,
            confidence,
            schema_version: SCHEMA_VERSION,
            reserved: 0,
        };
        self.publish_raw(ray)?;
        Ok(self.sequence)
    }

    /// Publishes a ray exactly as given.
    pub fn publish_raw(&mut self, ray: PointingRay) -> Result<(), IpcError> {
        self.publisher
            .loan_uninit()
            .map_err(|e| iceoryx_err("loaning a ray", e))?
            .write_payload(ray)
            .send()
            .map_err(|e| iceoryx_err("sending a ray", e))?;
        self.notifier
            .notify()
            .map_err(|e| iceoryx_err("notifying a ray", e))?;
        Ok(())
    }
}

/// A session id that differs between runs: the start time mixed with the
/// process id.
fn new_session() -> u64 {
    let mixed = now_ns() ^ (u64::from(std::process::id()) << 40);
    // splitmix64 finaliser, so that close start times give unrelated ids.
    let mut z = mixed.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
