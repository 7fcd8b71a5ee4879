//! Reading the raw wire channels of an MCAP recording back as frames.

use vref_scene::Side;
use vref_wire::bytes::{from_bytes, take_sample};
use vref_wire::{ObjectEntry, PointingRay, SnapshotHeader};

use crate::{Frame, RecordError, RecordedRay, RecordedSnapshot, WireChannel};

/// First bytes of every MCAP file.
pub const MCAP_MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// The feeds' frames (snapshots of both views, rays) of an MCAP file, in
/// file order; other channels (the Foxglove ones, the decision) are
/// skipped.
pub fn mcap_frames(bytes: &[u8]) -> Result<Vec<Frame>, RecordError> {
    let stream = mcap::MessageStream::new(bytes).map_err(RecordError::Mcap)?;
    let mut frames = Vec::new();
    for (index, message) in stream.enumerate() {
        let message = message.map_err(RecordError::Mcap)?;
        let Some(channel) = WireChannel::from_topic(&message.channel.topic) else {
            continue;
        };
        let wire = |source| RecordError::Wire {
            topic: channel.topic(),
            message: index as u64,
            source,
        };
        let frame = match channel {
            WireChannel::RobotSnapshot | WireChannel::HumanSnapshot => {
                let side = if channel == WireChannel::RobotSnapshot {
                    Side::Robot
                } else {
                    Side::Human
                };
                let (header, entries) =
                    take_sample::<SnapshotHeader, ObjectEntry>("snapshot", &message.data)
                        .map_err(wire)?;
                Frame::Snapshot(RecordedSnapshot::from_wire(side, &header, &entries))
            }
            WireChannel::Gesture => {
                let ray: PointingRay = from_bytes("pointing ray", &message.data).map_err(wire)?;
                Frame::Gesture(RecordedRay::from_wire(&ray))
            }
            WireChannel::Decision => continue,
        };
        frames.push(frame);
    }
    Ok(frames)
}

/// Every frame of a recording in either format: MCAP (by its magic) or
/// vref's own bincode frames.
pub fn read_frames(bytes: &[u8]) -> Result<Vec<Frame>, RecordError> {
    if bytes.starts_with(MCAP_MAGIC) {
        return mcap_frames(bytes);
    }
    crate::RecordingReader::new(bytes)?.collect()
}
