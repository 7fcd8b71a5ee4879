//! The binary encoding: each wire type's fields in declaration order,
//! little-endian, no padding (the wire types have none) — byte for byte
//! what the type holds in shared memory on a little-endian machine. Sizes
//! are checked exactly before a byte is read; a snapshot or decision is
//! its header followed by exactly the entries the header counts.

use std::mem::size_of;

use vref_wire::{
    Alternative, DecisionEntry, DecisionHeader, MAX_DECISION_PAIRS, MatcherStats, ObjectEntry,
    PointingRay, ReferenceAnswer, ReferenceQuery, SnapshotHeader,
};

use crate::CodecError;

// Each encoding is its type's shared-memory layout, so its size is the
// type's size (vref_wire::layout reads the same `size_of`).
pub const SNAPSHOT_HEADER_BYTES: usize = size_of::<SnapshotHeader>();
pub const OBJECT_ENTRY_BYTES: usize = size_of::<ObjectEntry>();
pub const RAY_BYTES: usize = size_of::<PointingRay>();
pub const QUERY_BYTES: usize = size_of::<ReferenceQuery>();
pub const ANSWER_BYTES: usize = size_of::<ReferenceAnswer>();
pub const STATS_BYTES: usize = size_of::<MatcherStats>();
pub const DECISION_HEADER_BYTES: usize = size_of::<DecisionHeader>();
pub const DECISION_ENTRY_BYTES: usize = size_of::<DecisionEntry>();

/// A snapshot: the header, then `entries` (the header's `object_count`
/// is written as given).
pub fn encode_snapshot(header: &SnapshotHeader, entries: &[ObjectEntry]) -> Vec<u8> {
    let mut w = Writer::with_capacity(SNAPSHOT_HEADER_BYTES + entries.len() * OBJECT_ENTRY_BYTES);
    w.u64s(&[header.session, header.sequence, header.timestamp_ns]);
    w.u32s(&[
        header.schema_version,
        header.side,
        header.object_count,
        header.feature_dim,
    ]);
    w.bytes(&header.frame_name);
    w.f32s(&header.up);
    w.u32s(&[header.flags]);
    for e in entries {
        w.u64s(&[e.track_id]);
        w.f32s(&e.position);
        w.f32s(&e.position_sigma);
        w.f32s(&e.feature);
    }
    w.0
}

/// A snapshot's header and its objects; the payload must carry exactly
/// the objects the header counts.
pub fn decode_snapshot(bytes: &[u8]) -> Result<(SnapshotHeader, Vec<ObjectEntry>), CodecError> {
    let carried = sized_list("snapshot", bytes, SNAPSHOT_HEADER_BYTES, OBJECT_ENTRY_BYTES)?;
    let mut r = Reader::new(bytes);
    let header = SnapshotHeader {
        session: r.u64(),
        sequence: r.u64(),
        timestamp_ns: r.u64(),
        schema_version: r.u32(),
        side: r.u32(),
        object_count: r.u32(),
        feature_dim: r.u32(),
        frame_name: r.array(),
        up: r.f32s(),
        flags: r.u32(),
    };
    if header.object_count as usize != carried {
        return Err(CodecError::Count {
            count: header.object_count,
            carried,
        });
    }
    let entries = (0..carried)
        .map(|_| ObjectEntry {
            track_id: r.u64(),
            position: r.f32s(),
            position_sigma: r.f32s(),
            feature: r.f32s(),
        })
        .collect();
    Ok((header, entries))
}

pub fn encode_ray(ray: &PointingRay) -> Vec<u8> {
    let mut w = Writer::with_capacity(RAY_BYTES);
    w.u64s(&[ray.session, ray.sequence, ray.timestamp_ns]);
    w.f32s(&ray.origin);
    w.f32s(&ray.direction);
    w.f32s(&[ray.cone_half_angle, ray.confidence]);
    w.u32s(&[ray.schema_version, ray.reserved]);
    w.0
}

pub fn decode_ray(bytes: &[u8]) -> Result<PointingRay, CodecError> {
    exact("pointing ray", bytes, RAY_BYTES)?;
    let mut r = Reader::new(bytes);
    Ok(PointingRay {
        session: r.u64(),
        sequence: r.u64(),
        timestamp_ns: r.u64(),
        origin: r.f32s(),
        direction: r.f32s(),
        cone_half_angle: r.f32(),
        confidence: r.f32(),
        schema_version: r.u32(),
        reserved: r.u32(),
    })
}

pub fn encode_query(q: &ReferenceQuery) -> Vec<u8> {
    let mut w = Writer::with_capacity(QUERY_BYTES);
    w.u64s(&[q.request_id, q.human_object_id]);
    w.f32s(&q.ray_origin);
    w.f32s(&q.ray_direction);
    w.f32s(&[q.cone_half_angle]);
    w.u32s(&[q.kind, q.schema_version, q.reserved]);
    w.0
}

pub fn decode_query(bytes: &[u8]) -> Result<ReferenceQuery, CodecError> {
    exact("reference query", bytes, QUERY_BYTES)?;
    let mut r = Reader::new(bytes);
    Ok(ReferenceQuery {
        request_id: r.u64(),
        human_object_id: r.u64(),
        ray_origin: r.f32s(),
        ray_direction: r.f32s(),
        cone_half_angle: r.f32(),
        kind: r.u32(),
        schema_version: r.u32(),
        reserved: r.u32(),
    })
}

pub fn encode_answer(a: &ReferenceAnswer) -> Vec<u8> {
    let mut w = Writer::with_capacity(ANSWER_BYTES);
    w.u64s(&[
        a.request_id,
        a.human_object_id,
        a.robot_track_id,
        a.robot_sequence,
        a.human_sequence,
        a.robot_age_us,
        a.human_age_us,
        a.solve_age_us,
        a.ray_age_us,
    ]);
    w.f32s(&a.position);
    w.f32s(&a.human_frame_position);
    w.f32s(&[a.confidence]);
    w.u32s(&[a.status, a.alternative_count, a.schema_version]);
    for alt in &a.alternatives {
        w.u64s(&[alt.robot_track_id]);
        w.f32s(&[alt.confidence]);
        w.u32s(&[alt.reserved]);
    }
    w.u32s(&[a.flags, a.refusal]);
    w.0
}

pub fn decode_answer(bytes: &[u8]) -> Result<ReferenceAnswer, CodecError> {
    exact("reference answer", bytes, ANSWER_BYTES)?;
    let mut r = Reader::new(bytes);
    Ok(ReferenceAnswer {
        request_id: r.u64(),
        human_object_id: r.u64(),
        robot_track_id: r.u64(),
        robot_sequence: r.u64(),
        human_sequence: r.u64(),
        robot_age_us: r.u64(),
        human_age_us: r.u64(),
        solve_age_us: r.u64(),
        ray_age_us: r.u64(),
        position: r.f32s(),
        human_frame_position: r.f32s(),
        confidence: r.f32(),
        status: r.u32(),
        alternative_count: r.u32(),
        schema_version: r.u32(),
        alternatives: std::array::from_fn(|_| Alternative {
            robot_track_id: r.u64(),
            confidence: r.f32(),
            reserved: r.u32(),
        }),
        flags: r.u32(),
        refusal: r.u32(),
    })
}

pub fn encode_stats(s: &MatcherStats) -> Vec<u8> {
    let mut w = Writer::with_capacity(STATS_BYTES);
    w.u64s(&[s.started_ns, s.taken_ns, s.uptime_ms]);
    w.u64s(&s.snapshots_received);
    w.u64s(&s.snapshots_accepted);
    w.u64s(&s.rejected);
    w.u64s(&s.answers);
    w.u64s(&[s.solves, s.rss_kb]);
    w.u32s(&[s.pid, s.schema_version]);
    w.0
}

pub fn decode_stats(bytes: &[u8]) -> Result<MatcherStats, CodecError> {
    exact("matcher statistics", bytes, STATS_BYTES)?;
    let mut r = Reader::new(bytes);
    Ok(MatcherStats {
        started_ns: r.u64(),
        taken_ns: r.u64(),
        uptime_ms: r.u64(),
        snapshots_received: r.u64s(),
        snapshots_accepted: r.u64s(),
        rejected: r.u64s(),
        answers: r.u64s(),
        solves: r.u64(),
        rss_kb: r.u64(),
        pid: r.u32(),
        schema_version: r.u32(),
    })
}

/// A decision: the header, then `entries` (the header's `pair_count` is
/// written as given).
pub fn encode_decision(h: &DecisionHeader, entries: &[DecisionEntry]) -> Vec<u8> {
    let mut w = Writer::with_capacity(DECISION_HEADER_BYTES + entries.len() * DECISION_ENTRY_BYTES);
    w.u64s(&[
        h.robot_session,
        h.robot_sequence,
        h.robot_timestamp_ns,
        h.human_session,
        h.human_sequence,
        h.human_timestamp_ns,
        h.solved_ns,
        h.solve_us,
        h.solve_index,
    ]);
    w.f32s(&h.rotation);
    w.f32s(&h.translation);
    w.u32s(&[h.pair_count, h.flags]);
    w.bytes(&h.method);
    w.u32s(&[h.schema_version]);
    w.f32s(&[h.residual_median]);
    for e in entries {
        w.u64s(&[e.human_track_id, e.robot_track_id]);
        w.f32s(&[e.confidence]);
        w.u32s(&[e.status, e.flags]);
        w.f32s(&[e.residual]);
    }
    w.0
}

pub fn decode_decision(bytes: &[u8]) -> Result<(DecisionHeader, Vec<DecisionEntry>), CodecError> {
    let carried = sized_list(
        "decision",
        bytes,
        DECISION_HEADER_BYTES,
        DECISION_ENTRY_BYTES,
    )?;
    if carried > MAX_DECISION_PAIRS {
        return Err(CodecError::TooMany {
            what: "decision",
            len: carried,
            max: MAX_DECISION_PAIRS,
        });
    }
    let mut r = Reader::new(bytes);
    let header = DecisionHeader {
        robot_session: r.u64(),
        robot_sequence: r.u64(),
        robot_timestamp_ns: r.u64(),
        human_session: r.u64(),
        human_sequence: r.u64(),
        human_timestamp_ns: r.u64(),
        solved_ns: r.u64(),
        solve_us: r.u64(),
        solve_index: r.u64(),
        rotation: r.f32s(),
        translation: r.f32s(),
        pair_count: r.u32(),
        flags: r.u32(),
        method: r.array(),
        schema_version: r.u32(),
        residual_median: r.f32(),
    };
    if header.pair_count as usize != carried {
        return Err(CodecError::Count {
            count: header.pair_count,
            carried,
        });
    }
    let entries = (0..carried)
        .map(|_| DecisionEntry {
            human_track_id: r.u64(),
            robot_track_id: r.u64(),
            confidence: r.f32(),
            status: r.u32(),
            flags: r.u32(),
            residual: r.f32(),
        })
        .collect();
    Ok((header, entries))
}

fn exact(what: &'static str, bytes: &[u8], expected: usize) -> Result<(), CodecError> {
    if bytes.len() == expected {
        Ok(())
    } else {
        Err(CodecError::Size {
            what,
            bytes: bytes.len(),
            expected: expected.to_string(),
        })
    }
}

/// How many whole entries follow a header; anything but a header plus
/// whole entries is refused.
fn sized_list(
    what: &'static str,
    bytes: &[u8],
    header: usize,
    entry: usize,
) -> Result<usize, CodecError> {
    match bytes.len().checked_sub(header) {
        Some(rest) if rest % entry == 0 => Ok(rest / entry),
        _ => Err(CodecError::Size {
            what,
            bytes: bytes.len(),
            expected: format!("{header} + n x {entry}"),
        }),
    }
}

struct Writer(Vec<u8>);

impl Writer {
    fn with_capacity(n: usize) -> Self {
        Self(Vec::with_capacity(n))
    }

    fn u64s(&mut self, values: &[u64]) {
        for v in values {
            self.0.extend_from_slice(&v.to_le_bytes());
        }
    }

    fn u32s(&mut self, values: &[u32]) {
        for v in values {
            self.0.extend_from_slice(&v.to_le_bytes());
        }
    }

    fn f32s(&mut self, values: &[f32]) {
        for v in values {
            self.0.extend_from_slice(&v.to_le_bytes());
        }
    }

    fn bytes(&mut self, bytes: &[u8]) {
        self.0.extend_from_slice(bytes);
    }
}

/// Reads fields in order from a payload whose size was checked first;
/// past the end (which the size checks rule out) it reads zeros rather
/// than panic.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: 0 }
    }

    fn array<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0; N];
        if let Some(chunk) = self.bytes.get(self.at..self.at + N) {
            out.copy_from_slice(chunk);
        }
        self.at += N;
        out
    }

    fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.array())
    }

    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.array())
    }

    fn f32(&mut self) -> f32 {
        f32::from_le_bytes(self.array())
    }

    fn u64s<const N: usize>(&mut self) -> [u64; N] {
        std::array::from_fn(|_| self.u64())
    }

    fn f32s<const N: usize>(&mut self) -> [f32; N] {
        std::array::from_fn(|_| self.f32())
    }
}

#[cfg(test)]
mod tests {
    use vref_wire::{AnswerStatus, FRAME_NAME_LEN, SCHEMA_VERSION, SideCode};

    use super::*;

    /// The size of `name` in vref-wire's published layout.
    fn layout_size(name: &str) -> usize {
        vref_wire::layout::wire_types()
            .into_iter()
            .find(|t| t.name == name)
            .map(|t| t.size)
            .unwrap_or_else(|| panic!("{name} is not in the layout"))
    }

    /// Every encoder writes every byte of its type's layout: a field
    /// added to a wire type fails here until the codec writes it.
    #[test]
    fn encodings_fill_the_published_layout() {
        assert_eq!(
            encode_snapshot(&header(2), &[entry(1), entry(2)]).len(),
            layout_size("SnapshotHeader") + 2 * layout_size("ObjectEntry")
        );
        let ray = decode_ray(&[0; RAY_BYTES]).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(encode_ray(&ray).len(), layout_size("PointingRay"));
        assert_eq!(
            encode_query(&ReferenceQuery::latest_gesture()).len(),
            layout_size("ReferenceQuery")
        );
        assert_eq!(
            encode_answer(&ReferenceAnswer::empty(1, AnswerStatus::Ok)).len(),
            layout_size("ReferenceAnswer")
        );
        assert_eq!(
            encode_stats(&MatcherStats::default()).len(),
            layout_size("MatcherStats")
        );
        let entries = [DecisionEntry::default(); 3];
        assert_eq!(
            encode_decision(&DecisionHeader::default(), &entries).len(),
            layout_size("DecisionHeader") + 3 * layout_size("DecisionEntry")
        );
    }

    fn entry(id: u64) -> ObjectEntry {
        ObjectEntry {
            track_id: id,
            position: [0.1 * id as f32, -0.25, 1.5],
            position_sigma: [0.01, 0.02, 0.03],
            feature: std::array::from_fn(|i| i as f32 / 7.0),
        }
    }

    fn header(count: u32) -> SnapshotHeader {
        let mut frame_name = [0; FRAME_NAME_LEN];
        frame_name[..7].copy_from_slice(b"headset");
        SnapshotHeader {
            session: 0x0102_0304_0506_0708,
            sequence: 9,
            timestamp_ns: 1_700_000_000_000_000_000,
            schema_version: SCHEMA_VERSION,
            side: SideCode::Human as u32,
            object_count: count,
            feature_dim: 4,
            frame_name,
            up: [0.0; 3],
            flags: 0,
        }
    }

    #[test]
    fn snapshots_round_trip_little_endian() {
        let entries = vec![entry(1), entry(2), entry(3)];
        let bytes = encode_snapshot(&header(3), &entries);
        assert_eq!(bytes.len(), SNAPSHOT_HEADER_BYTES + 3 * OBJECT_ENTRY_BYTES);
        // The session is the first field, least significant byte first.
        assert_eq!(&bytes[..8], &[8, 7, 6, 5, 4, 3, 2, 1]);
        assert_eq!(decode_snapshot(&bytes), Ok((header(3), entries)));
    }

    #[test]
    fn an_up_vector_and_its_flag_round_trip() {
        let mut h = header(1);
        h.set_up(Some([0.25, -1.0, f32::MIN_POSITIVE]));
        let bytes = encode_snapshot(&h, &[entry(1)]);
        let (back, _) = decode_snapshot(&bytes).unwrap();
        assert_eq!(back, h);
        assert_eq!(back.up(), Some([0.25, -1.0, f32::MIN_POSITIVE]));
        // The flags are the header's last field, before the objects.
        let flags = SNAPSHOT_HEADER_BYTES - 4;
        assert_eq!(
            bytes[flags..flags + 4],
            SnapshotHeader::FLAG_UP.to_le_bytes()
        );
        assert_eq!(
            decode_snapshot(&encode_snapshot(&header(0), &[]))
                .unwrap()
                .0
                .up(),
            None
        );
    }

    #[test]
    fn snapshots_of_the_wrong_size_or_count_are_refused() {
        let bytes = encode_snapshot(&header(2), &[entry(1), entry(2)]);
        for cut in [0, 10, SNAPSHOT_HEADER_BYTES - 1, bytes.len() - 1] {
            assert!(
                matches!(decode_snapshot(&bytes[..cut]), Err(CodecError::Size { .. })),
                "{cut}"
            );
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(matches!(
            decode_snapshot(&longer),
            Err(CodecError::Size { .. })
        ));
        let lying = encode_snapshot(&header(5), &[entry(1), entry(2)]);
        assert_eq!(
            decode_snapshot(&lying),
            Err(CodecError::Count {
                count: 5,
                carried: 2
            })
        );
        let empty = encode_snapshot(&header(0), &[]);
        assert_eq!(decode_snapshot(&empty), Ok((header(0), vec![])));
    }

    #[test]
    fn rays_queries_answers_stats_and_decisions_round_trip() {
        let ray = PointingRay {
            session: 1,
            sequence: 2,
            timestamp_ns: 3,
            origin: [0.0, -0.1, 0.2],
            direction: [0.0, 0.0, 1.0],
            cone_half_angle: 0.1,
            confidence: 0.9,
            schema_version: SCHEMA_VERSION,
            reserved: 0,
        };
        assert_eq!(decode_ray(&encode_ray(&ray)), Ok(ray));
        assert!(decode_ray(&encode_ray(&ray)[1..]).is_err());

        let query = ReferenceQuery {
            request_id: 7,
            human_object_id: 4,
            ray_origin: [1.0, 2.0, 3.0],
            ray_direction: [0.0, 1.0, 0.0],
            cone_half_angle: 0.2,
            kind: 1,
            schema_version: SCHEMA_VERSION,
            reserved: 0,
        };
        assert_eq!(decode_query(&encode_query(&query)), Ok(query));

        let mut answer = ReferenceAnswer::empty(11, AnswerStatus::Ambiguous);
        answer.robot_track_id = 1003;
        answer.position = [0.5, 0.25, 1.0];
        answer.human_frame_position = [0.1, 0.2, 0.3];
        answer.solve_age_us = 1234;
        answer.ray_age_us = 99;
        answer.alternative_count = 2;
        answer.alternatives[0].robot_track_id = 1004;
        answer.alternatives[1].confidence = 0.25;
        answer.flags = ReferenceAnswer::FLAG_SOLVED | ReferenceAnswer::FLAG_HUMAN_POSITION;
        assert_eq!(decode_answer(&encode_answer(&answer)), Ok(answer));

        let mut stats = MatcherStats {
            pid: 77,
            solves: 5,
            ..MatcherStats::default()
        };
        stats.rejected[3] = 9;
        stats.answers[4] = 2;
        stats.snapshots_accepted = [10, 20];
        assert_eq!(decode_stats(&encode_stats(&stats)), Ok(stats));

        let mut header = DecisionHeader {
            pair_count: 2,
            solve_index: 3,
            flags: DecisionHeader::FLAG_MOTION,
            ..DecisionHeader::default()
        };
        header.method[..5].copy_from_slice(b"rigid");
        let entries = vec![
            DecisionEntry {
                human_track_id: 1,
                robot_track_id: 1001,
                confidence: 0.9,
                status: 0,
                flags: DecisionEntry::FLAG_PARTNER,
                residual: 0.0,
            },
            DecisionEntry {
                human_track_id: 2,
                status: 2,
                ..DecisionEntry::default()
            },
        ];
        let bytes = encode_decision(&header, &entries);
        assert_eq!(decode_decision(&bytes), Ok((header, entries)));
        assert!(decode_decision(&bytes[..bytes.len() - 3]).is_err());
    }
}
