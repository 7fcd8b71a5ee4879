//! Arbitrary bytes as a snapshot a hostile publisher could have written:
//! the input of the snapshot fuzz target (fuzz/) and of the test that
//! runs its committed corpus, so both exercise the same decoding.

use vref_scene::Side;

use crate::{FRAME_NAME_LEN, MAX_FEATURE_DIM, ObjectEntry, SnapshotHeader};

/// Bytes of the header part: session, sequence, timestamp (u64 each),
/// schema version, side, object count, feature dimension (u32 each), the
/// frame name, the up vector (3 f32), the flags (u32): the header's own
/// layout.
pub const HEADER_BYTES: usize = 3 * 8 + 4 * 4 + FRAME_NAME_LEN + 3 * 4 + 4;
/// Bytes per object: a 16-bit track id (so that duplicates are common),
/// position and sigma (3 f32 each), 4 feature values repeated over the
/// whole feature array.
pub const ENTRY_BYTES: usize = 2 + 6 * 4 + 4 * 4;

/// A decoded input: the side it claims to arrive on, its header, its
/// slice (as long as the bytes allow, whatever the header's count says).
#[derive(Debug, Clone, PartialEq)]
pub struct FuzzSnapshot {
    pub expected: Side,
    pub header: SnapshotHeader,
    pub entries: Vec<ObjectEntry>,
}

/// First byte: the expected side (lowest bit); then the header (missing
/// bytes read as zero); then whole objects. Little-endian throughout.
pub fn snapshot_from_bytes(data: &[u8]) -> FuzzSnapshot {
    let (first, rest) = data.split_first().unwrap_or((&0, &[]));
    let expected = if first & 1 == 0 {
        Side::Robot
    } else {
        Side::Human
    };
    let mut head = [0u8; HEADER_BYTES];
    let n = rest.len().min(HEADER_BYTES);
    head[..n].copy_from_slice(&rest[..n]);
    let mut r = Reader(&head);
    let mut header = SnapshotHeader {
        session: r.u64(),
        sequence: r.u64(),
        timestamp_ns: r.u64(),
        schema_version: r.u32(),
        side: r.u32(),
        object_count: r.u32(),
        feature_dim: r.u32(),
        frame_name: [0; FRAME_NAME_LEN],
        up: [0.0; 3],
        flags: 0,
    };
    header.frame_name.copy_from_slice(r.take(FRAME_NAME_LEN));
    header.up = [r.f32(), r.f32(), r.f32()];
    header.flags = r.u32();
    let entries = rest
        .get(HEADER_BYTES..)
        .unwrap_or(&[])
        .chunks_exact(ENTRY_BYTES)
        .map(|chunk| {
            let mut r = Reader(chunk);
            let track_id = u64::from(r.u16());
            let position = [r.f32(), r.f32(), r.f32()];
            let position_sigma = [r.f32(), r.f32(), r.f32()];
            let values = [r.f32(), r.f32(), r.f32(), r.f32()];
            let mut feature = [0.0; MAX_FEATURE_DIM];
            for (i, v) in feature.iter_mut().enumerate() {
                *v = values[i % values.len()];
            }
            ObjectEntry {
                track_id,
                position,
                position_sigma,
                feature,
            }
        })
        .collect();
    FuzzSnapshot {
        expected,
        header,
        entries,
    }
}

/// The inverse of [`snapshot_from_bytes`] for entries whose track ids fit
/// 16 bits and whose features repeat every 4 values: seeds for the
/// corpus.
pub fn snapshot_to_bytes(s: &FuzzSnapshot) -> Vec<u8> {
    let h = &s.header;
    let mut out = vec![u8::from(s.expected == Side::Human)];
    for v in [h.session, h.sequence, h.timestamp_ns] {
        out.extend(v.to_le_bytes());
    }
    for v in [h.schema_version, h.side, h.object_count, h.feature_dim] {
        out.extend(v.to_le_bytes());
    }
    out.extend(h.frame_name);
    for v in h.up {
        out.extend(v.to_le_bytes());
    }
    out.extend(h.flags.to_le_bytes());
    for e in &s.entries {
        out.extend(u16::try_from(e.track_id).unwrap_or(u16::MAX).to_le_bytes());
        for v in e
            .position
            .iter()
            .chain(&e.position_sigma)
            .chain(&e.feature[..4])
        {
            out.extend(v.to_le_bytes());
        }
    }
    out
}

struct Reader<'a>(&'a [u8]);

impl<'a> Reader<'a> {
    /// The next `n` bytes; the callers never ask past the end (fixed
    /// layouts over buffers of the right size), and get zeros if they do.
    fn take(&mut self, n: usize) -> &'a [u8] {
        const ZEROS: [u8; 64] = [0; 64];
        if self.0.len() < n {
            return &ZEROS[..n.min(ZEROS.len())];
        }
        let (head, tail) = self.0.split_at(n);
        self.0 = tail;
        head
    }

    fn array<const N: usize>(&mut self) -> [u8; N] {
        let mut a = [0; N];
        let bytes = self.take(N);
        a[..bytes.len()].copy_from_slice(bytes);
        a
    }

    fn u16(&mut self) -> u16 {
        u16::from_le_bytes(self.array())
    }

    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.array())
    }

    fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.array())
    }

    fn f32(&mut self) -> f32 {
        f32::from_le_bytes(self.array())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SCHEMA_VERSION;

    #[test]
    fn bytes_round_trip_and_short_input_reads_as_zeros() {
        let mut frame_name = [0; FRAME_NAME_LEN];
        frame_name[..4].copy_from_slice(b"cam0");
        let snapshot = FuzzSnapshot {
            expected: Side::Human,
            header: SnapshotHeader {
                session: 7,
                sequence: 9,
                timestamp_ns: 11,
                schema_version: SCHEMA_VERSION,
                side: 1,
                object_count: 1,
                feature_dim: 4,
                frame_name,
                up: [0.0, -1.0, 0.25],
                flags: SnapshotHeader::FLAG_UP,
            },
            entries: vec![ObjectEntry {
                track_id: 300,
                position: [0.1, -0.2, 1.5],
                position_sigma: [0.01; 3],
                feature: std::array::from_fn(|i| (i % 4) as f32),
            }],
        };
        let bytes = snapshot_to_bytes(&snapshot);
        assert_eq!(bytes.len(), 1 + HEADER_BYTES + ENTRY_BYTES);
        assert_eq!(snapshot_from_bytes(&bytes), snapshot);

        let short = snapshot_from_bytes(&[1, 5]);
        assert_eq!(short.expected, Side::Human);
        assert_eq!(short.header.session, 5);
        assert!(short.entries.is_empty());
        assert_eq!(snapshot_from_bytes(&[]).expected, Side::Robot);
    }
}
