//! The JSON encoding: what a headset app in any language writes and what
//! a monitor reads. Field names are the wire's (and, for answers, those of
//! `vref query --json`); unknown fields are errors, as in vref.toml, so a
//! misspelt field is refused rather than silently defaulted. Numbers that
//! JSON cannot hold (NaN, infinities) cannot be written at all, and values
//! beyond f32 are refused as out of range when decoding.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use vref_reference::RejectReason;
use vref_wire::{
    Alternative, AnswerStatus, DecisionEntry, DecisionHeader, FRAME_NAME_LEN, MAX_ALTERNATIVES,
    MAX_FEATURE_DIM, MatcherStats, ObjectEntry, PointingRay, QueryKind, ReferenceAnswer,
    ReferenceQuery, SCHEMA_VERSION, SideCode, SnapshotHeader,
};

use crate::CodecError;

/// The frame a headset snapshot is in when it names none.
pub const DEFAULT_HEADSET_FRAME: &str = "headset";

/// One object of a snapshot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectJson {
    pub track_id: u64,
    /// Metres, in the snapshot's camera frame.
    pub position: [f32; 3],
    /// One standard deviation per axis, metres; 0 if unknown.
    #[serde(default)]
    pub position_sigma: [f32; 3],
    /// The appearance feature; the same length for every object, empty
    /// if there is none.
    #[serde(default)]
    pub feature: Vec<f32>,
}

/// A headset snapshot as the headset sends it (`<prefix>/human/snapshot`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SnapshotIn {
    /// Random per headset app run.
    pub session: u64,
    /// Increases within a session.
    pub sequence: u64,
    /// The headset's camera frame; default "headset".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame_name: Option<String>,
    /// Which way is up (against gravity) in that frame, any non-zero
    /// length; absent if unknown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<[f32; 3]>,
    pub objects: Vec<ObjectJson>,
}

/// A snapshot as the bridge publishes it (`<prefix>/robot/snapshot`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SnapshotOut {
    pub session: u64,
    pub sequence: u64,
    /// Capture time, nanoseconds since the Unix epoch (robot clock).
    pub timestamp_ns: u64,
    pub frame_name: String,
    /// Which way is up in that frame (as the snapshot carried it, unit
    /// length from a vref feed); absent if unknown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<[f32; 3]>,
    pub objects: Vec<ObjectJson>,
}

/// A pointing ray as the headset sends it (`<prefix>/human/gesture`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RayJson {
    pub session: u64,
    pub sequence: u64,
    pub origin: [f32; 3],
    pub direction: [f32; 3],
    pub cone_half_angle: f32,
    pub confidence: f32,
}

/// A remote reference query (payload of a get on `<prefix>/reference`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum QueryJson {
    HumanObject {
        #[serde(default)]
        request_id: u64,
        human_object_id: u64,
    },
    Ray {
        #[serde(default)]
        request_id: u64,
        ray_origin: [f32; 3],
        ray_direction: [f32; 3],
        cone_half_angle: f32,
    },
    LatestGesture {
        #[serde(default)]
        request_id: u64,
    },
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AlternativeJson {
    pub robot_track_id: u64,
    pub confidence: f32,
}

/// An answer: the fields of `vref query --json` (less the client's own
/// round trip) and the schema-2 ones.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnswerJson {
    pub status: String,
    pub request_id: u64,
    pub human_object_id: u64,
    pub robot_track_id: u64,
    pub position: [f32; 3],
    pub confidence: f32,
    pub alternatives: Vec<AlternativeJson>,
    pub robot_sequence: u64,
    pub human_sequence: u64,
    pub robot_age_us: u64,
    pub human_age_us: u64,
    pub solve_age_us: u64,
    pub ray_age_us: u64,
    /// The answered object in the human view's frame, when the matcher
    /// gave it.
    pub human_frame_position: Option<[f32; 3]>,
    /// ... mapped there through the estimated motion between the views
    /// (else the human object's own position).
    pub human_position_from_motion: bool,
    /// A real solve made the answering solution (else it was carried over
    /// unchanged); answers never wait for a solve.
    pub solved: bool,
    /// Why a `stale` or `not_ready` answer has nothing fresher: the
    /// matcher's reject reason of the snapshot it last refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refusal: Option<String>,
}

/// The matcher's statistics (`<prefix>/matcher/stats`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StatsJson {
    pub started_ns: u64,
    pub taken_ns: u64,
    pub uptime_ms: u64,
    pub pid: u32,
    pub rss_kb: u64,
    pub solves: u64,
    pub snapshots_received: BySide,
    pub snapshots_accepted: BySide,
    /// Rejected messages by reason (the matcher's reason names), non-zero
    /// ones only.
    pub rejected: BTreeMap<String, u64>,
    /// Queries answered, by status name.
    pub answers: BTreeMap<String, u64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BySide {
    pub robot: u64,
    pub human: u64,
}

/// The matcher's decision (`<prefix>/matcher/decision`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DecisionJson {
    pub robot_session: u64,
    pub robot_sequence: u64,
    pub robot_timestamp_ns: u64,
    pub human_session: u64,
    pub human_sequence: u64,
    pub human_timestamp_ns: u64,
    pub solved_ns: u64,
    pub solve_us: u64,
    pub solve_index: u64,
    pub method: String,
    /// Human camera frame to robot camera frame, when the method
    /// estimated it.
    pub motion: Option<MotionJson>,
    pub pairs: Vec<PairJson>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionJson {
    /// `q = R p + t`, `R` row-major.
    pub rotation: [f32; 9],
    pub translation: [f32; 3],
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PairJson {
    pub human_track_id: u64,
    /// `null`: no partner.
    pub robot_track_id: Option<u64>,
    pub confidence: f32,
    pub status: String,
}

fn parse<'a, T: Deserialize<'a>>(what: &'static str, bytes: &'a [u8]) -> Result<T, CodecError> {
    serde_json::from_slice(bytes).map_err(|e| CodecError::Json {
        what,
        message: e.to_string(),
    })
}

fn to_bytes(value: &impl Serialize) -> Vec<u8> {
    // Serialising these types cannot fail: no maps with non-string keys,
    // no fallible Serialize impls.
    serde_json::to_vec(value).unwrap_or_default()
}

/// A headset snapshot into the wire's form (header and entries, as a
/// publisher would write them into shared memory), for validation. The
/// feature dimension is the objects' common feature length.
pub fn decode_snapshot(bytes: &[u8]) -> Result<(SnapshotHeader, Vec<ObjectEntry>), CodecError> {
    let snapshot: SnapshotIn = parse("snapshot", bytes)?;
    let frame = snapshot
        .frame_name
        .as_deref()
        .unwrap_or(DEFAULT_HEADSET_FRAME);
    if frame.len() > FRAME_NAME_LEN {
        return Err(CodecError::FrameNameTooLong {
            len: frame.len(),
            max: FRAME_NAME_LEN,
        });
    }
    let mut frame_name = [0; FRAME_NAME_LEN];
    frame_name[..frame.len()].copy_from_slice(frame.as_bytes());
    let dim = snapshot.objects.first().map_or(0, |o| o.feature.len());
    if let Some(odd) = snapshot.objects.iter().find(|o| o.feature.len() != dim) {
        return Err(CodecError::FeatureLengths {
            id: odd.track_id,
            len: odd.feature.len(),
            first: dim,
        });
    }
    let entries = snapshot
        .objects
        .iter()
        .map(|o| {
            let mut feature = [0.0; MAX_FEATURE_DIM];
            let used = o.feature.len().min(MAX_FEATURE_DIM);
            feature[..used].copy_from_slice(&o.feature[..used]);
            ObjectEntry {
                track_id: o.track_id,
                position: o.position,
                position_sigma: o.position_sigma,
                feature,
            }
        })
        .collect::<Vec<_>>();
    let mut header = SnapshotHeader {
        session: snapshot.session,
        sequence: snapshot.sequence,
        timestamp_ns: 0,
        schema_version: SCHEMA_VERSION,
        side: SideCode::Human as u32,
        object_count: u32::try_from(entries.len()).unwrap_or(u32::MAX),
        // Longer than the wire holds: validation refuses it by this.
        feature_dim: u32::try_from(dim).unwrap_or(u32::MAX),
        frame_name,
        up: [0.0; 3],
        flags: 0,
    };
    // Checked by validation, as from shared memory: a zero or infinite
    // up vector is refused there.
    header.set_up(snapshot.up);
    Ok((header, entries))
}

/// A snapshot as published; `entries` are the header's objects.
pub fn encode_snapshot(header: &SnapshotHeader, entries: &[ObjectEntry]) -> Vec<u8> {
    let dim = (header.feature_dim as usize).min(MAX_FEATURE_DIM);
    to_bytes(&SnapshotOut {
        session: header.session,
        sequence: header.sequence,
        timestamp_ns: header.timestamp_ns,
        frame_name: zero_padded(&header.frame_name),
        up: header.up(),
        objects: entries
            .iter()
            .map(|e| ObjectJson {
                track_id: e.track_id,
                position: e.position,
                position_sigma: e.position_sigma,
                feature: e.feature[..dim].to_vec(),
            })
            .collect(),
    })
}

/// A headset snapshot as JSON (for headset simulators and examples).
pub fn encode_snapshot_in(snapshot: &SnapshotIn) -> Vec<u8> {
    to_bytes(snapshot)
}

pub fn decode_ray(bytes: &[u8]) -> Result<PointingRay, CodecError> {
    let ray: RayJson = parse("pointing ray", bytes)?;
    Ok(PointingRay {
        session: ray.session,
        sequence: ray.sequence,
        timestamp_ns: 0,
        origin: ray.origin,
        direction: ray.direction,
        cone_half_angle: ray.cone_half_angle,
        confidence: ray.confidence,
        schema_version: SCHEMA_VERSION,
        reserved: 0,
    })
}

pub fn encode_ray(ray: &PointingRay) -> Vec<u8> {
    to_bytes(&RayJson {
        session: ray.session,
        sequence: ray.sequence,
        origin: ray.origin,
        direction: ray.direction,
        cone_half_angle: ray.cone_half_angle,
        confidence: ray.confidence,
    })
}

pub fn decode_query(bytes: &[u8]) -> Result<ReferenceQuery, CodecError> {
    let query: QueryJson = parse("reference query", bytes)?;
    let (request_id, query) = match query {
        QueryJson::HumanObject {
            request_id,
            human_object_id,
        } => (request_id, ReferenceQuery::human_object(human_object_id)),
        QueryJson::Ray {
            request_id,
            ray_origin,
            ray_direction,
            cone_half_angle,
        } => (
            request_id,
            ReferenceQuery::ray(ray_origin, ray_direction, cone_half_angle),
        ),
        QueryJson::LatestGesture { request_id } => (request_id, ReferenceQuery::latest_gesture()),
    };
    Ok(ReferenceQuery {
        request_id,
        ..query
    })
}

/// A query as JSON. JSON names only the three kinds; any other code is
/// written as a human-object query.
pub fn encode_query(q: &ReferenceQuery) -> Vec<u8> {
    let query = match q.kind {
        k if k == QueryKind::Ray as u32 => QueryJson::Ray {
            request_id: q.request_id,
            ray_origin: q.ray_origin,
            ray_direction: q.ray_direction,
            cone_half_angle: q.cone_half_angle,
        },
        k if k == QueryKind::LatestGesture as u32 => QueryJson::LatestGesture {
            request_id: q.request_id,
        },
        _ => QueryJson::HumanObject {
            request_id: q.request_id,
            human_object_id: q.human_object_id,
        },
    };
    to_bytes(&query)
}

impl From<&ReferenceAnswer> for AnswerJson {
    fn from(a: &ReferenceAnswer) -> Self {
        let flag = |bit| a.flags & bit != 0;
        Self {
            status: a.status().name().to_owned(),
            request_id: a.request_id,
            human_object_id: a.human_object_id,
            robot_track_id: a.robot_track_id,
            position: a.position,
            confidence: a.confidence,
            alternatives: a
                .alternatives()
                .iter()
                .map(|alt| AlternativeJson {
                    robot_track_id: alt.robot_track_id,
                    confidence: alt.confidence,
                })
                .collect(),
            robot_sequence: a.robot_sequence,
            human_sequence: a.human_sequence,
            robot_age_us: a.robot_age_us,
            human_age_us: a.human_age_us,
            solve_age_us: a.solve_age_us,
            ray_age_us: a.ray_age_us,
            human_frame_position: flag(ReferenceAnswer::FLAG_HUMAN_POSITION)
                .then_some(a.human_frame_position),
            human_position_from_motion: flag(ReferenceAnswer::FLAG_HUMAN_POSITION_FROM_MOTION),
            solved: flag(ReferenceAnswer::FLAG_SOLVED),
            refusal: flag(ReferenceAnswer::FLAG_REFUSAL)
                .then(|| RejectReason::ALL.get(a.refusal as usize))
                .flatten()
                .map(|r| r.name().to_owned()),
        }
    }
}

impl AnswerJson {
    /// Back into the wire's answer; bits JSON does not carry are 0.
    pub fn to_answer(&self) -> Result<ReferenceAnswer, CodecError> {
        let status = AnswerStatus::ALL
            .into_iter()
            .find(|s| s.name() == self.status)
            .ok_or_else(|| CodecError::Status(self.status.clone()))?;
        if self.alternatives.len() > MAX_ALTERNATIVES {
            return Err(CodecError::TooMany {
                what: "alternatives",
                len: self.alternatives.len(),
                max: MAX_ALTERNATIVES,
            });
        }
        let mut answer = ReferenceAnswer::empty(self.request_id, status);
        answer.human_object_id = self.human_object_id;
        answer.robot_track_id = self.robot_track_id;
        answer.robot_sequence = self.robot_sequence;
        answer.human_sequence = self.human_sequence;
        answer.robot_age_us = self.robot_age_us;
        answer.human_age_us = self.human_age_us;
        answer.solve_age_us = self.solve_age_us;
        answer.ray_age_us = self.ray_age_us;
        answer.position = self.position;
        answer.confidence = self.confidence;
        for (slot, alt) in answer.alternatives.iter_mut().zip(&self.alternatives) {
            *slot = Alternative {
                robot_track_id: alt.robot_track_id,
                confidence: alt.confidence,
                reserved: 0,
            };
        }
        answer.alternative_count = u32::try_from(self.alternatives.len()).unwrap_or(0);
        if self.solved {
            answer.flags |= ReferenceAnswer::FLAG_SOLVED;
        }
        if let Some(p) = self.human_frame_position {
            answer.human_frame_position = p;
            answer.flags |= ReferenceAnswer::FLAG_HUMAN_POSITION;
        }
        if self.human_position_from_motion {
            answer.flags |= ReferenceAnswer::FLAG_HUMAN_POSITION_FROM_MOTION;
        }
        if let Some(name) = &self.refusal {
            let reason = RejectReason::ALL
                .iter()
                .position(|r| r.name() == name)
                .ok_or_else(|| CodecError::Refusal(name.clone()))?;
            answer.refusal = reason as u32;
            answer.flags |= ReferenceAnswer::FLAG_REFUSAL;
        }
        Ok(answer)
    }
}

pub fn encode_answer(a: &ReferenceAnswer) -> Vec<u8> {
    to_bytes(&AnswerJson::from(a))
}

pub fn decode_answer(bytes: &[u8]) -> Result<ReferenceAnswer, CodecError> {
    parse::<AnswerJson>("reference answer", bytes)?.to_answer()
}

impl From<&MatcherStats> for StatsJson {
    fn from(s: &MatcherStats) -> Self {
        let rejected = s
            .rejected
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
            .map(|(i, n)| {
                let name = RejectReason::ALL
                    .get(i)
                    .map_or_else(|| format!("reason_{i}"), |r| r.name().to_owned());
                (name, *n)
            })
            .collect();
        let answers = AnswerStatus::ALL
            .into_iter()
            .map(|status| (status.name().to_owned(), s.answered(status)))
            .collect();
        let by_side = |v: [u64; 2]| BySide {
            robot: v[SideCode::Robot as usize],
            human: v[SideCode::Human as usize],
        };
        Self {
            started_ns: s.started_ns,
            taken_ns: s.taken_ns,
            uptime_ms: s.uptime_ms,
            pid: s.pid,
            rss_kb: s.rss_kb,
            solves: s.solves,
            snapshots_received: by_side(s.snapshots_received),
            snapshots_accepted: by_side(s.snapshots_accepted),
            rejected,
            answers,
        }
    }
}

pub fn encode_stats(s: &MatcherStats) -> Vec<u8> {
    to_bytes(&StatsJson::from(s))
}

pub fn decode_stats(bytes: &[u8]) -> Result<StatsJson, CodecError> {
    parse("matcher statistics", bytes)
}

pub fn encode_decision(h: &DecisionHeader, entries: &[DecisionEntry]) -> Vec<u8> {
    let status = |code| {
        AnswerStatus::from_code(code)
            .map_or_else(|| format!("status_{code}"), |s| s.name().to_owned())
    };
    to_bytes(&DecisionJson {
        robot_session: h.robot_session,
        robot_sequence: h.robot_sequence,
        robot_timestamp_ns: h.robot_timestamp_ns,
        human_session: h.human_session,
        human_sequence: h.human_sequence,
        human_timestamp_ns: h.human_timestamp_ns,
        solved_ns: h.solved_ns,
        solve_us: h.solve_us,
        solve_index: h.solve_index,
        method: zero_padded(&h.method),
        motion: (h.flags & DecisionHeader::FLAG_MOTION != 0).then_some(MotionJson {
            rotation: h.rotation,
            translation: h.translation,
        }),
        pairs: entries
            .iter()
            .map(|e| PairJson {
                human_track_id: e.human_track_id,
                robot_track_id: (e.flags & DecisionEntry::FLAG_PARTNER != 0)
                    .then_some(e.robot_track_id),
                confidence: e.confidence,
                status: status(e.status),
            })
            .collect(),
    })
}

pub fn decode_decision(bytes: &[u8]) -> Result<DecisionJson, CodecError> {
    parse("decision", bytes)
}

pub fn decode_snapshot_out(bytes: &[u8]) -> Result<SnapshotOut, CodecError> {
    parse("snapshot", bytes)
}

/// Text up to the first zero byte; bytes that are not UTF-8 are replaced.
fn zero_padded(bytes: &[u8]) -> String {
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_headset_snapshot_becomes_the_wire_form() {
        let text = br#"{"session": 5, "sequence": 2, "objects": [
            {"track_id": 1, "position": [0.1, 0.0, 0.8], "feature": [1, 0, 0]},
            {"track_id": 2, "position": [-0.1, 0.0, 0.9], "position_sigma": [0.01, 0.01, 0.02],
             "feature": [0, 1, 0]}]}"#;
        let (header, entries) = decode_snapshot(text).unwrap();
        assert_eq!((header.session, header.sequence), (5, 2));
        assert_eq!(
            (header.object_count, header.feature_dim, header.side),
            (2, 3, 1)
        );
        assert_eq!(zero_padded(&header.frame_name), "headset");
        assert_eq!(entries[1].position_sigma, [0.01, 0.01, 0.02]);
        assert_eq!(entries[0].position_sigma, [0.0; 3]);
        assert_eq!(entries[1].feature[..4], [0.0, 1.0, 0.0, 0.0]);
    }

    #[test]
    fn an_up_vector_goes_in_and_out_as_json() {
        let text = br#"{"session": 5, "sequence": 2, "up": [0, -0.6, 0.8], "objects": [
            {"track_id": 1, "position": [0.1, 0.0, 0.8]}]}"#;
        let (header, entries) = decode_snapshot(text).unwrap();
        assert_eq!(header.up(), Some([0.0, -0.6, 0.8]));
        let out = decode_snapshot_out(&encode_snapshot(&header, &entries)).unwrap();
        assert_eq!(out.up, Some([0.0, -0.6, 0.8]));
        // Without one: absent in, absent out.
        let text = br#"{"session": 5, "sequence": 3, "objects": []}"#;
        let (header, entries) = decode_snapshot(text).unwrap();
        assert_eq!((header.up(), header.flags), (None, 0));
        let out = encode_snapshot(&header, &entries);
        let value: serde_json::Value = serde_json::from_slice(&out).unwrap();
        assert!(value.get("up").is_none(), "{value}");
        // A headset simulator's snapshot carries it too.
        let snapshot = SnapshotIn {
            session: 1,
            sequence: 1,
            frame_name: None,
            up: Some([1.0, 0.0, 0.0]),
            objects: vec![],
        };
        let (header, _) = decode_snapshot(&encode_snapshot_in(&snapshot)).unwrap();
        assert_eq!(header.up(), Some([1.0, 0.0, 0.0]));
    }

    #[test]
    fn bad_json_is_refused_naming_what_is_wrong() {
        let cases: [(&[u8], &str); 7] = [
            (b"{", "EOF"),
            (b"[1, 2]", "struct"),
            (
                br#"{"session": 1, "sequence": 1, "objects": [], "timestamp_ns": 3}"#,
                "timestamp_ns",
            ),
            (br#"{"session": 1, "objects": []}"#, "sequence"),
            (
                br#"{"session": 1, "sequence": 1, "objects": [{"track_id": 1, "position": [NaN, 0, 0]}]}"#,
                "expected value",
            ),
            (
                br#"{"session": 1, "sequence": 1, "objects": [{"track_id": 1, "position": [0, 0]}]}"#,
                "array",
            ),
            (
                br#"{"session": -1, "sequence": 1, "objects": []}"#,
                "-1",
            ),
        ];
        for (text, says) in cases {
            match decode_snapshot(text) {
                Err(CodecError::Json { message, .. }) => {
                    assert!(message.contains(says), "{message} should say {says}")
                }
                other => panic!("{}: {other:?}", String::from_utf8_lossy(text)),
            }
        }
    }

    #[test]
    fn features_of_different_lengths_and_long_frame_names_are_refused() {
        let mixed = br#"{"session": 1, "sequence": 1, "objects": [
            {"track_id": 1, "position": [0, 0, 1], "feature": [1, 0]},
            {"track_id": 7, "position": [0, 0, 1], "feature": [1]}]}"#;
        assert_eq!(
            decode_snapshot(mixed),
            Err(CodecError::FeatureLengths {
                id: 7,
                len: 1,
                first: 2
            })
        );
        let long = format!(
            r#"{{"session": 1, "sequence": 1, "frame_name": "{}", "objects": []}}"#,
            "x".repeat(33)
        );
        assert!(matches!(
            decode_snapshot(long.as_bytes()),
            Err(CodecError::FrameNameTooLong { len: 33, .. })
        ));
    }

    #[test]
    fn too_long_features_are_left_for_validation_to_refuse() {
        let feature: Vec<f32> = vec![0.5; MAX_FEATURE_DIM + 1];
        let snapshot = SnapshotIn {
            session: 1,
            sequence: 1,
            frame_name: None,
            up: None,
            objects: vec![ObjectJson {
                track_id: 1,
                position: [0.0, 0.0, 1.0],
                position_sigma: [0.0; 3],
                feature,
            }],
        };
        let (header, entries) = decode_snapshot(&encode_snapshot_in(&snapshot)).unwrap();
        let limits = vref_scene::Limits::default();
        assert!(matches!(
            vref_wire::validate_snapshot(&header, &entries, vref_scene::Side::Human, &limits),
            Err(vref_wire::WireError::FeatureDimTooLarge { .. })
        ));
    }

    #[test]
    fn queries_of_each_kind_decode_and_round_trip() {
        let q = decode_query(br#"{"kind": "human_object", "human_object_id": 3}"#).unwrap();
        assert_eq!(
            (q.kind, q.human_object_id, q.request_id),
            (QueryKind::HumanObject as u32, 3, 0)
        );
        let q = decode_query(
            br#"{"kind": "ray", "request_id": 9, "ray_origin": [0, 0, 0],
                 "ray_direction": [0, 0, 1], "cone_half_angle": 0.1}"#,
        )
        .unwrap();
        assert_eq!((q.kind, q.request_id), (QueryKind::Ray as u32, 9));
        assert_eq!(decode_query(&encode_query(&q)), Ok(q));
        let q = decode_query(br#"{"kind": "latest_gesture"}"#).unwrap();
        assert_eq!(q.kind, QueryKind::LatestGesture as u32);
        for bad in [
            &br#"{"kind": "everything"}"#[..],
            br#"{"human_object_id": 3}"#,
            br#"{"kind": "latest_gesture", "human_object_id": 3}"#,
        ] {
            assert!(
                decode_query(bad).is_err(),
                "{}",
                String::from_utf8_lossy(bad)
            );
        }
    }

    #[test]
    fn answers_round_trip_through_json() {
        let mut a = ReferenceAnswer::empty(4, AnswerStatus::Stale);
        a.robot_track_id = 1002;
        a.human_object_id = 2;
        a.position = [0.123_456_79, -1e-7, 3.0];
        a.confidence = 0.875;
        a.alternative_count = 1;
        a.alternatives[0] = Alternative {
            robot_track_id: 1003,
            confidence: 0.1,
            reserved: 0,
        };
        a.robot_age_us = 600_000;
        a.solve_age_us = 12;
        a.human_frame_position = [0.5, 0.5, 0.5];
        a.flags = ReferenceAnswer::FLAG_HUMAN_POSITION | ReferenceAnswer::FLAG_SOLVED;
        let text = encode_answer(&a);
        let value: serde_json::Value = serde_json::from_slice(&text).unwrap();
        assert_eq!(value["status"], "stale");
        assert_eq!(value["human_frame_position"][0], 0.5);
        assert_eq!(decode_answer(&text), Ok(a));
        // Without the flag there is no position to show.
        a.flags = 0;
        let value: serde_json::Value = serde_json::from_slice(&encode_answer(&a)).unwrap();
        assert!(value["human_frame_position"].is_null());
        let lost = String::from_utf8(text)
            .unwrap()
            .replace("\"stale\"", "\"lost\"");
        assert_eq!(
            decode_answer(lost.as_bytes()),
            Err(CodecError::Status("lost".to_owned()))
        );
        // A stale answer that names the refusal behind it, by name.
        a.refusal = RejectReason::FeatureDimOtherSide as u32;
        a.flags = ReferenceAnswer::FLAG_REFUSAL;
        a.human_frame_position = [0.0; 3];
        let text = encode_answer(&a);
        let value: serde_json::Value = serde_json::from_slice(&text).unwrap();
        assert_eq!(value["refusal"], "feature_dim_other_side");
        assert_eq!(decode_answer(&text), Ok(a));
        a.flags = 0;
        let value: serde_json::Value = serde_json::from_slice(&encode_answer(&a)).unwrap();
        assert!(value.get("refusal").is_none());
    }

    #[test]
    fn stats_and_decisions_are_named_not_indexed() {
        let mut s = MatcherStats::default();
        s.rejected[RejectReason::NonFinitePosition as usize] = 3;
        s.answers[AnswerStatus::Ok as usize] = 10;
        s.snapshots_accepted = [5, 6];
        let json = decode_stats(&encode_stats(&s)).unwrap();
        assert_eq!(json.rejected.get("non_finite_position"), Some(&3));
        assert_eq!(json.rejected.len(), 1);
        assert_eq!(json.answers.get("ok"), Some(&10));
        assert_eq!(json.answers.get("stale"), Some(&0));
        assert_eq!(json.snapshots_accepted, BySide { robot: 5, human: 6 });

        let mut h = DecisionHeader::default();
        h.method[..5].copy_from_slice(b"rigid");
        let entries = [
            DecisionEntry {
                human_track_id: 1,
                robot_track_id: 1001,
                confidence: 0.9,
                status: AnswerStatus::Ok as u32,
                flags: DecisionEntry::FLAG_PARTNER,
                residual: 0.0,
            },
            DecisionEntry {
                human_track_id: 2,
                status: AnswerStatus::NoMatch as u32,
                ..DecisionEntry::default()
            },
        ];
        let d = decode_decision(&encode_decision(&h, &entries)).unwrap();
        assert_eq!(d.method, "rigid");
        assert_eq!(d.motion, None);
        assert_eq!(d.pairs[0].robot_track_id, Some(1001));
        assert_eq!(d.pairs[1].robot_track_id, None);
        assert_eq!(d.pairs[1].status, "no_match");
    }
}
