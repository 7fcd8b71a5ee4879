//! The wire messages as bytes, for recordings: each type's `#[repr(C)]`
//! layout as a little-endian machine holds it in shared memory (every type
//! has no implicit padding, so the layout is the fields in order), written
//! field by field so that a file means the same on any machine. A
//! snapshot or a decision is its header followed by every entry of the
//! sample's slice, so that what a faulty publisher sent (a count that
//! disagrees with the slice, say) is kept as it was.

use crate::{
    DecisionEntry, DecisionHeader, FRAME_NAME_LEN, MAX_ALTERNATIVES, MAX_ANSWER_STATUSES,
    MAX_FEATURE_DIM, MAX_REJECT_REASONS, MatcherStats, ObjectEntry, PointingRay, ReferenceAnswer,
    SnapshotHeader,
};

/// Why bytes are not a wire message.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum BytesError {
    #[error("{what}: {len} bytes is not {head} plus a whole number of {entry}-byte entries")]
    Length {
        what: &'static str,
        len: usize,
        head: usize,
        entry: usize,
    },
}

/// A type laid out on the wire as its fields in order, little-endian.
pub trait WireBytes: Sized {
    /// Its size in shared memory, which is its size here.
    const SIZE: usize;
    fn put(&self, out: &mut Vec<u8>);
    /// Reads one value from the front of `input`; `None` if too short.
    fn take(input: &mut &[u8]) -> Option<Self>;
}

fn put_u64(out: &mut Vec<u8>, v: u64) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn put_u32(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn put_f32s(out: &mut Vec<u8>, v: &[f32]) {
    for x in v {
        out.extend_from_slice(&x.to_le_bytes());
    }
}

fn put_u64s(out: &mut Vec<u8>, v: &[u64]) {
    for x in v {
        put_u64(out, *x);
    }
}

fn chunk<const N: usize>(input: &mut &[u8]) -> Option<[u8; N]> {
    let (head, rest) = input.split_first_chunk::<N>()?;
    *input = rest;
    Some(*head)
}

fn take_u64(input: &mut &[u8]) -> Option<u64> {
    chunk::<8>(input).map(u64::from_le_bytes)
}

fn take_u32(input: &mut &[u8]) -> Option<u32> {
    chunk::<4>(input).map(u32::from_le_bytes)
}

fn take_f32(input: &mut &[u8]) -> Option<f32> {
    chunk::<4>(input).map(f32::from_le_bytes)
}

fn take_f32s<const N: usize>(input: &mut &[u8]) -> Option<[f32; N]> {
    let mut out = [0.0; N];
    for x in &mut out {
        *x = take_f32(input)?;
    }
    Some(out)
}

fn take_u64s<const N: usize>(input: &mut &[u8]) -> Option<[u64; N]> {
    let mut out = [0; N];
    for x in &mut out {
        *x = take_u64(input)?;
    }
    Some(out)
}

impl WireBytes for SnapshotHeader {
    const SIZE: usize = 3 * 8 + 4 * 4 + FRAME_NAME_LEN + 3 * 4 + 4;

    fn put(&self, out: &mut Vec<u8>) {
        put_u64s(out, &[self.session, self.sequence, self.timestamp_ns]);
        for v in [
            self.schema_version,
            self.side,
            self.object_count,
            self.feature_dim,
        ] {
            put_u32(out, v);
        }
        out.extend_from_slice(&self.frame_name);
        put_f32s(out, &self.up);
        put_u32(out, self.flags);
    }

    fn take(input: &mut &[u8]) -> Option<Self> {
        Some(Self {
            session: take_u64(input)?,
            sequence: take_u64(input)?,
            timestamp_ns: take_u64(input)?,
            schema_version: take_u32(input)?,
            side: take_u32(input)?,
            object_count: take_u32(input)?,
            feature_dim: take_u32(input)?,
            frame_name: chunk::<FRAME_NAME_LEN>(input)?,
            up: take_f32s(input)?,
            flags: take_u32(input)?,
        })
    }
}

impl WireBytes for ObjectEntry {
    const SIZE: usize = 8 + 6 * 4 + MAX_FEATURE_DIM * 4;

    fn put(&self, out: &mut Vec<u8>) {
        put_u64(out, self.track_id);
        put_f32s(out, &self.position);
        put_f32s(out, &self.position_sigma);
        put_f32s(out, &self.feature);
    }

    fn take(input: &mut &[u8]) -> Option<Self> {
        Some(Self {
            track_id: take_u64(input)?,
            position: take_f32s(input)?,
            position_sigma: take_f32s(input)?,
            feature: take_f32s(input)?,
        })
    }
}

impl WireBytes for PointingRay {
    const SIZE: usize = 3 * 8 + 10 * 4;

    fn put(&self, out: &mut Vec<u8>) {
        put_u64s(out, &[self.session, self.sequence, self.timestamp_ns]);
        put_f32s(out, &self.origin);
        put_f32s(out, &self.direction);
        put_f32s(out, &[self.cone_half_angle, self.confidence]);
        put_u32(out, self.schema_version);
        put_u32(out, self.reserved);
    }

    fn take(input: &mut &[u8]) -> Option<Self> {
        Some(Self {
            session: take_u64(input)?,
            sequence: take_u64(input)?,
            timestamp_ns: take_u64(input)?,
            origin: take_f32s(input)?,
            direction: take_f32s(input)?,
            cone_half_angle: take_f32(input)?,
            confidence: take_f32(input)?,
            schema_version: take_u32(input)?,
            reserved: take_u32(input)?,
        })
    }
}

impl WireBytes for DecisionHeader {
    const SIZE: usize = 9 * 8 + 12 * 4 + 2 * 4 + 16 + 2 * 4;

    fn put(&self, out: &mut Vec<u8>) {
        put_u64s(
            out,
            &[
                self.robot_session,
                self.robot_sequence,
                self.robot_timestamp_ns,
                self.human_session,
                self.human_sequence,
                self.human_timestamp_ns,
                self.solved_ns,
                self.solve_us,
                self.solve_index,
            ],
        );
        put_f32s(out, &self.rotation);
        put_f32s(out, &self.translation);
        put_u32(out, self.pair_count);
        put_u32(out, self.flags);
        out.extend_from_slice(&self.method);
        put_u32(out, self.schema_version);
        put_f32s(out, &[self.residual_median]);
    }

    fn take(input: &mut &[u8]) -> Option<Self> {
        Some(Self {
            robot_session: take_u64(input)?,
            robot_sequence: take_u64(input)?,
            robot_timestamp_ns: take_u64(input)?,
            human_session: take_u64(input)?,
            human_sequence: take_u64(input)?,
            human_timestamp_ns: take_u64(input)?,
            solved_ns: take_u64(input)?,
            solve_us: take_u64(input)?,
            solve_index: take_u64(input)?,
            rotation: take_f32s(input)?,
            translation: take_f32s(input)?,
            pair_count: take_u32(input)?,
            flags: take_u32(input)?,
            method: chunk::<16>(input)?,
            schema_version: take_u32(input)?,
            residual_median: take_f32(input)?,
        })
    }
}

impl WireBytes for DecisionEntry {
    const SIZE: usize = 2 * 8 + 4 * 4;

    fn put(&self, out: &mut Vec<u8>) {
        put_u64s(out, &[self.human_track_id, self.robot_track_id]);
        put_f32s(out, &[self.confidence]);
        for v in [self.status, self.flags] {
            put_u32(out, v);
        }
        put_f32s(out, &[self.residual]);
    }

    fn take(input: &mut &[u8]) -> Option<Self> {
        Some(Self {
            human_track_id: take_u64(input)?,
            robot_track_id: take_u64(input)?,
            confidence: take_f32(input)?,
            status: take_u32(input)?,
            flags: take_u32(input)?,
            residual: take_f32(input)?,
        })
    }
}

impl WireBytes for ReferenceAnswer {
    const SIZE: usize = 9 * 8 + 10 * 4 + MAX_ALTERNATIVES * 16 + 2 * 4;

    fn put(&self, out: &mut Vec<u8>) {
        put_u64s(
            out,
            &[
                self.request_id,
                self.human_object_id,
                self.robot_track_id,
                self.robot_sequence,
                self.human_sequence,
                self.robot_age_us,
                self.human_age_us,
                self.solve_age_us,
                self.ray_age_us,
            ],
        );
        put_f32s(out, &self.position);
        put_f32s(out, &self.human_frame_position);
        put_f32s(out, &[self.confidence]);
        for v in [self.status, self.alternative_count, self.schema_version] {
            put_u32(out, v);
        }
        for a in &self.alternatives {
            put_u64(out, a.robot_track_id);
            put_f32s(out, &[a.confidence]);
            put_u32(out, a.reserved);
        }
        put_u32(out, self.flags);
        put_u32(out, self.refusal);
    }

    fn take(input: &mut &[u8]) -> Option<Self> {
        let mut answer = ReferenceAnswer::empty(0, crate::AnswerStatus::Ok);
        answer.request_id = take_u64(input)?;
        answer.human_object_id = take_u64(input)?;
        answer.robot_track_id = take_u64(input)?;
        answer.robot_sequence = take_u64(input)?;
        answer.human_sequence = take_u64(input)?;
        answer.robot_age_us = take_u64(input)?;
        answer.human_age_us = take_u64(input)?;
        answer.solve_age_us = take_u64(input)?;
        answer.ray_age_us = take_u64(input)?;
        answer.position = take_f32s(input)?;
        answer.human_frame_position = take_f32s(input)?;
        answer.confidence = take_f32(input)?;
        answer.status = take_u32(input)?;
        answer.alternative_count = take_u32(input)?;
        answer.schema_version = take_u32(input)?;
        for a in &mut answer.alternatives {
            a.robot_track_id = take_u64(input)?;
            a.confidence = take_f32(input)?;
            a.reserved = take_u32(input)?;
        }
        answer.flags = take_u32(input)?;
        answer.refusal = take_u32(input)?;
        Some(answer)
    }
}

impl WireBytes for MatcherStats {
    const SIZE: usize = (3 + 2 + 2 + MAX_REJECT_REASONS + MAX_ANSWER_STATUSES + 2) * 8 + 2 * 4;

    fn put(&self, out: &mut Vec<u8>) {
        put_u64s(out, &[self.started_ns, self.taken_ns, self.uptime_ms]);
        put_u64s(out, &self.snapshots_received);
        put_u64s(out, &self.snapshots_accepted);
        put_u64s(out, &self.rejected);
        put_u64s(out, &self.answers);
        put_u64s(out, &[self.solves, self.rss_kb]);
        put_u32(out, self.pid);
        put_u32(out, self.schema_version);
    }

    fn take(input: &mut &[u8]) -> Option<Self> {
        Some(Self {
            started_ns: take_u64(input)?,
            taken_ns: take_u64(input)?,
            uptime_ms: take_u64(input)?,
            snapshots_received: take_u64s(input)?,
            snapshots_accepted: take_u64s(input)?,
            rejected: take_u64s(input)?,
            answers: take_u64s(input)?,
            solves: take_u64(input)?,
            rss_kb: take_u64(input)?,
            pid: take_u32(input)?,
            schema_version: take_u32(input)?,
        })
    }
}

/// A header and its slice as bytes, appended to `out`.
pub fn put_sample<H: WireBytes, E: WireBytes>(header: &H, entries: &[E], out: &mut Vec<u8>) {
    out.reserve(H::SIZE + entries.len() * E::SIZE);
    header.put(out);
    for e in entries {
        e.put(out);
    }
}

/// A header and its slice back from bytes; `what` names the message in
/// the error.
pub fn take_sample<H: WireBytes, E: WireBytes>(
    what: &'static str,
    bytes: &[u8],
) -> Result<(H, Vec<E>), BytesError> {
    let wrong = || BytesError::Length {
        what,
        len: bytes.len(),
        head: H::SIZE,
        entry: E::SIZE,
    };
    let body = bytes.len().checked_sub(H::SIZE).ok_or_else(wrong)?;
    if body % E::SIZE != 0 {
        return Err(wrong());
    }
    let mut input = bytes;
    let header = H::take(&mut input).ok_or_else(wrong)?;
    let entries = (0..body / E::SIZE)
        .map(|_| E::take(&mut input).ok_or_else(wrong))
        .collect::<Result<_, _>>()?;
    Ok((header, entries))
}

/// One value as bytes.
pub fn to_bytes<T: WireBytes>(value: &T) -> Vec<u8> {
    let mut out = Vec::with_capacity(T::SIZE);
    value.put(&mut out);
    out
}

/// One value back from exactly its bytes.
pub fn from_bytes<T: WireBytes>(what: &'static str, bytes: &[u8]) -> Result<T, BytesError> {
    let wrong = || BytesError::Length {
        what,
        len: bytes.len(),
        head: T::SIZE,
        entry: 0,
    };
    if bytes.len() != T::SIZE {
        return Err(wrong());
    }
    let mut input = bytes;
    T::take(&mut input).ok_or_else(wrong)
}

#[cfg(test)]
mod tests {
    use std::mem::size_of;

    use super::*;
    use crate::{Alternative, AnswerStatus};

    /// The sizes written are the sizes in shared memory, so the bytes are
    /// the layout (on a little-endian machine).
    #[test]
    fn byte_sizes_are_the_in_memory_sizes() {
        assert_eq!(SnapshotHeader::SIZE, size_of::<SnapshotHeader>());
        assert_eq!(ObjectEntry::SIZE, size_of::<ObjectEntry>());
        assert_eq!(PointingRay::SIZE, size_of::<PointingRay>());
        assert_eq!(DecisionHeader::SIZE, size_of::<DecisionHeader>());
        assert_eq!(DecisionEntry::SIZE, size_of::<DecisionEntry>());
        assert_eq!(ReferenceAnswer::SIZE, size_of::<ReferenceAnswer>());
        assert_eq!(MatcherStats::SIZE, size_of::<MatcherStats>());
        assert_eq!(
            to_bytes(&SnapshotHeader::default()).len(),
            SnapshotHeader::SIZE
        );
        assert_eq!(to_bytes(&MatcherStats::default()).len(), MatcherStats::SIZE);
    }

    fn entry(id: u64) -> ObjectEntry {
        let mut feature = [0.0; MAX_FEATURE_DIM];
        feature[0] = id as f32 * 0.5;
        feature[MAX_FEATURE_DIM - 1] = -1.25;
        ObjectEntry {
            track_id: id,
            position: [0.1, -0.2, f32::MIN_POSITIVE],
            position_sigma: [0.01, 0.02, 0.03],
            feature,
        }
    }

    #[test]
    fn a_snapshot_comes_back_bit_for_bit_with_its_whole_slice() {
        let header = SnapshotHeader {
            session: u64::MAX - 3,
            sequence: 17,
            timestamp_ns: 1_700_000_000_123_456_789,
            schema_version: 3,
            side: 1,
            // Disagrees with the slice: kept as sent.
            object_count: 5,
            feature_dim: 2,
            frame_name: *b"headset_camera\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0",
            // Not unit length, and a NaN: kept as sent too.
            up: [0.0, f32::NAN, -2.5],
            flags: SnapshotHeader::FLAG_UP,
        };
        let entries = [entry(1), entry(2), entry(3)];
        let mut bytes = Vec::new();
        put_sample(&header, &entries, &mut bytes);
        assert_eq!(bytes.len(), SnapshotHeader::SIZE + 3 * ObjectEntry::SIZE);
        let (h, e): (SnapshotHeader, Vec<ObjectEntry>) = take_sample("snapshot", &bytes).unwrap();
        // Bit for bit: NaN != NaN, so compare the up vector's bits.
        assert_eq!(h.up.map(f32::to_bits), header.up.map(f32::to_bits));
        assert_eq!(
            SnapshotHeader { up: [0.0; 3], ..h },
            SnapshotHeader {
                up: [0.0; 3],
                ..header
            }
        );
        assert_eq!(e, entries);
        // The first field is little-endian on any machine.
        assert_eq!(bytes[..8], (u64::MAX - 3).to_le_bytes());
    }

    #[test]
    fn rays_decisions_answers_and_stats_come_back() {
        let ray = PointingRay {
            session: 1,
            sequence: 2,
            timestamp_ns: 3,
            origin: [0.0, 0.1, 0.2],
            direction: [0.0, 0.0, 1.0],
            cone_half_angle: 0.1,
            confidence: 0.9,
            schema_version: 2,
            reserved: 0,
        };
        assert_eq!(from_bytes::<PointingRay>("ray", &to_bytes(&ray)), Ok(ray));

        let header = DecisionHeader {
            solve_index: 9,
            flags: DecisionHeader::FLAG_MOTION,
            translation: [0.5, 0.0, -0.5],
            method: *b"rigid\0\0\0\0\0\0\0\0\0\0\0",
            ..DecisionHeader::default()
        };
        let entries = [DecisionEntry {
            human_track_id: 4,
            robot_track_id: 40,
            confidence: 0.75,
            status: AnswerStatus::Ok as u32,
            flags: DecisionEntry::FLAG_PARTNER,
            residual: 0.0,
        }];
        let mut bytes = Vec::new();
        put_sample(&header, &entries, &mut bytes);
        let back: (DecisionHeader, Vec<DecisionEntry>) = take_sample("decision", &bytes).unwrap();
        assert_eq!(back, (header, entries.to_vec()));

        let mut answer = ReferenceAnswer::empty(7, AnswerStatus::Ambiguous);
        answer.alternative_count = 1;
        answer.alternatives[0] = Alternative {
            robot_track_id: 8,
            confidence: 0.25,
            reserved: 0,
        };
        answer.human_frame_position = [1.0, 2.0, 3.0];
        answer.flags = ReferenceAnswer::FLAG_HUMAN_POSITION;
        assert_eq!(from_bytes("answer", &to_bytes(&answer)), Ok(answer));

        let stats = MatcherStats {
            solves: 12,
            rejected: [3; MAX_REJECT_REASONS],
            ..MatcherStats::default()
        };
        assert_eq!(from_bytes("stats", &to_bytes(&stats)), Ok(stats));
    }

    #[test]
    fn wrong_lengths_are_errors_not_panics() {
        let mut bytes = Vec::new();
        put_sample(&SnapshotHeader::default(), &[entry(1)], &mut bytes);
        for len in [
            0,
            10,
            SnapshotHeader::SIZE - 1,
            bytes.len() - 1,
            bytes.len() + 1,
        ] {
            let mut b = bytes.clone();
            b.resize(len, 0);
            let r = take_sample::<SnapshotHeader, ObjectEntry>("snapshot", &b);
            assert!(matches!(r, Err(BytesError::Length { len: l, .. }) if l == len));
        }
        // A header alone is a snapshot of no objects.
        let r =
            take_sample::<SnapshotHeader, ObjectEntry>("snapshot", &bytes[..SnapshotHeader::SIZE]);
        assert_eq!(r.map(|(_, e)| e.len()), Ok(0));
        assert!(from_bytes::<PointingRay>("ray", &[0; 3]).is_err());
    }
}
