//! Reading the raw wire channels of an MCAP recording back as frames.

use vref_scene::Side;
use vref_wire::bytes::{BytesError, WireBytes, from_bytes, take_sample};
use vref_wire::{FRAME_NAME_LEN, ObjectEntry, PointingRay, SnapshotHeader};

use crate::{Frame, RecordError, RecordedRay, RecordedSnapshot, WireChannel};

/// First bytes of every MCAP file.
pub const MCAP_MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// The feeds' frames (snapshots of both views, rays) of an MCAP file, in
/// file order; other channels (the Foxglove ones, the decision) are
/// skipped.
pub fn mcap_frames(bytes: &[u8]) -> Result<Vec<Frame>, RecordError> {
    mcap_frames_with(bytes, false)
}

/// `up_to_a_cut`: `bytes` are a file's whole records without its end
/// (no footer, no closing magic).
pub(crate) fn mcap_frames_with(bytes: &[u8], up_to_a_cut: bool) -> Result<Vec<Frame>, RecordError> {
    let stream = if up_to_a_cut {
        mcap::MessageStream::new_with_options(bytes, mcap::read::Options::IgnoreEndMagic.into())
    } else {
        mcap::MessageStream::new(bytes)
    }
    .map_err(RecordError::Mcap)?;
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
                let version = message
                    .channel
                    .schema
                    .as_ref()
                    .and_then(|s| WireChannel::schema_version_of(&s.data));
                let data = match version {
                    Some(v) if v < FIRST_SCHEMA_WITH_UP => {
                        std::borrow::Cow::Owned(without_up(&message.data).ok_or_else(|| {
                            wire(BytesError::Length {
                                what: "schema 2 snapshot",
                                len: message.data.len(),
                                head: SCHEMA_2_HEADER_BYTES,
                                entry: ObjectEntry::SIZE,
                            })
                        })?)
                    }
                    _ => std::borrow::Cow::Borrowed(&*message.data),
                };
                let (header, entries) =
                    take_sample::<SnapshotHeader, ObjectEntry>("snapshot", &data).map_err(wire)?;
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

/// The wire schema whose snapshot header first carried the up vector and
/// flags (appended to the header of schema 2).
const FIRST_SCHEMA_WITH_UP: u32 = 3;
/// Bytes of the snapshot header before schema 3: three u64, four u32, the
/// frame name.
const SCHEMA_2_HEADER_BYTES: usize = 3 * 8 + 4 * 4 + FRAME_NAME_LEN;

/// A snapshot message of schema 2 in today's layout: the header's new
/// fields (up vector, flags) inserted as zeros, which is "up unknown";
/// `None` if it is too short for even the old header.
fn without_up(data: &[u8]) -> Option<Vec<u8>> {
    let (head, entries) = data.split_at_checked(SCHEMA_2_HEADER_BYTES)?;
    let added = SnapshotHeader::SIZE - SCHEMA_2_HEADER_BYTES;
    let mut out = Vec::with_capacity(data.len() + added);
    out.extend_from_slice(head);
    out.resize(out.len() + added, 0);
    out.extend_from_slice(entries);
    Some(out)
}

/// Every frame of a recording in either format: MCAP (by its magic) or
/// vref's own bincode frames.
pub fn read_frames(bytes: &[u8]) -> Result<Vec<Frame>, RecordError> {
    if bytes.is_empty() {
        return Err(RecordError::Empty);
    }
    if bytes.starts_with(MCAP_MAGIC) {
        return mcap_frames(bytes);
    }
    crate::RecordingReader::new(bytes)?.collect()
}
