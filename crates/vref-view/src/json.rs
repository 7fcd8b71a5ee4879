//! Answers, the matcher's statistics and its decision as JSON messages
//! (Foxglove's Raw Messages and Plot panels read them), each with a JSON
//! schema. Every field is always present with one type (no nulls, no
//! `oneOf`: Foxglove's schema reader takes neither); a `has_...` flag says
//! whether a value means anything.

use serde_json::{Value, json};
use vref_wire::ipc::Decision;
use vref_wire::{AnswerStatus, DecisionEntry, DecisionHeader, MatcherStats, ReferenceAnswer};

use crate::state::Asked;

/// An answer the viewer asked for.
pub fn answer(asked: &Asked) -> Value {
    let a = &asked.answer;
    json!({
        "status": a.status().name(),
        "request_id": a.request_id,
        "human_object_id": a.human_object_id,
        "robot_track_id": a.robot_track_id,
        "confidence": a.confidence,
        "position": a.position,
        "has_human_frame_position": a.flags & ReferenceAnswer::FLAG_HUMAN_POSITION != 0,
        "human_frame_position": a.human_frame_position,
        "human_frame_position_from_motion":
            a.flags & ReferenceAnswer::FLAG_HUMAN_POSITION_FROM_MOTION != 0,
        "solved": a.solved(),
        "alternatives": a.alternatives().iter().map(|alt| json!({
            "robot_track_id": alt.robot_track_id,
            "confidence": alt.confidence,
        })).collect::<Vec<_>>(),
        "robot_sequence": a.robot_sequence,
        "human_sequence": a.human_sequence,
        "robot_age_us": a.robot_age_us,
        "human_age_us": a.human_age_us,
        "solve_age_us": a.solve_age_us,
        "ray_age_us": a.ray_age_us,
        "round_trip_us": asked.round_trip_us,
    })
}

/// The matcher's statistics.
pub fn stats(s: &MatcherStats) -> Value {
    let answers: serde_json::Map<String, Value> = AnswerStatus::ALL
        .iter()
        .map(|st| (st.name().to_owned(), json!(s.answered(*st))))
        .collect();
    json!({
        "pid": s.pid,
        "uptime_ms": s.uptime_ms,
        "snapshots_received": {"robot": s.snapshots_received[0], "human": s.snapshots_received[1]},
        "snapshots_accepted": {"robot": s.snapshots_accepted[0], "human": s.snapshots_accepted[1]},
        "rejected_total": s.rejected_total(),
        "rejected_by_reason": s.rejected.to_vec(),
        "answers": answers,
        "answered_total": s.answered_total(),
        "solves": s.solves,
        "rss_kb": s.rss_kb,
    })
}

/// The matcher's decision: every human object's outcome.
pub fn decision(d: &Decision) -> Value {
    let h = &d.header;
    json!({
        "method": d.method(),
        "solve_index": h.solve_index,
        "solve_us": h.solve_us,
        "robot_sequence": h.robot_sequence,
        "human_sequence": h.human_sequence,
        "motion_estimated": h.flags & DecisionHeader::FLAG_MOTION != 0,
        "rotation": h.rotation,
        "translation": h.translation,
        "pairs": d.entries.iter().map(|e| json!({
            "human_track_id": e.human_track_id,
            "has_partner": e.flags & DecisionEntry::FLAG_PARTNER != 0,
            "robot_track_id": e.robot_track_id,
            "confidence": e.confidence,
            "status": AnswerStatus::from_code(e.status).map_or("unknown", AnswerStatus::name),
        })).collect::<Vec<_>>(),
    })
}

fn object(title: &str, properties: Value) -> Value {
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": title,
        "type": "object",
        "properties": properties,
    })
}

const INTEGER: &str = "integer";
const NUMBER: &str = "number";

fn t(kind: &str) -> Value {
    json!({ "type": kind })
}

fn vec3() -> Value {
    json!({"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3})
}

pub fn answer_schema() -> Value {
    object(
        "vref.Answer",
        json!({
            "status": t("string"),
            "request_id": t(INTEGER),
            "human_object_id": t(INTEGER),
            "robot_track_id": t(INTEGER),
            "confidence": t(NUMBER),
            "position": vec3(),
            "has_human_frame_position": t("boolean"),
            "human_frame_position": vec3(),
            "human_frame_position_from_motion": t("boolean"),
            "solved": t("boolean"),
            "alternatives": {"type": "array", "items": object("vref.Alternative", json!({
                "robot_track_id": t(INTEGER), "confidence": t(NUMBER)}))},
            "robot_sequence": t(INTEGER),
            "human_sequence": t(INTEGER),
            "robot_age_us": t(INTEGER),
            "human_age_us": t(INTEGER),
            "solve_age_us": t(INTEGER),
            "ray_age_us": t(INTEGER),
            "round_trip_us": t(INTEGER),
        }),
    )
}

pub fn stats_schema() -> Value {
    let sides = || {
        object(
            "vref.Sides",
            json!({"robot": t(INTEGER), "human": t(INTEGER)}),
        )
    };
    let answers: serde_json::Map<String, Value> = AnswerStatus::ALL
        .iter()
        .map(|st| (st.name().to_owned(), t(INTEGER)))
        .collect();
    object(
        "vref.MatcherStats",
        json!({
            "pid": t(INTEGER),
            "uptime_ms": t(INTEGER),
            "snapshots_received": sides(),
            "snapshots_accepted": sides(),
            "rejected_total": t(INTEGER),
            "rejected_by_reason": {"type": "array", "items": t(INTEGER)},
            "answers": object("vref.AnswersByStatus", Value::Object(answers)),
            "answered_total": t(INTEGER),
            "solves": t(INTEGER),
            "rss_kb": t(INTEGER),
        }),
    )
}

pub fn decision_schema() -> Value {
    object(
        "vref.Decision",
        json!({
            "method": t("string"),
            "solve_index": t(INTEGER),
            "solve_us": t(INTEGER),
            "robot_sequence": t(INTEGER),
            "human_sequence": t(INTEGER),
            "motion_estimated": t("boolean"),
            "rotation": {"type": "array", "items": t(NUMBER), "minItems": 9, "maxItems": 9},
            "translation": vec3(),
            "pairs": {"type": "array", "items": object("vref.Pair", json!({
                "human_track_id": t(INTEGER),
                "has_partner": t("boolean"),
                "robot_track_id": t(INTEGER),
                "confidence": t(NUMBER),
                "status": t("string"),
            }))},
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field a message carries is declared in its schema.
    fn declared(message: &Value, schema: &Value) {
        let properties = schema["properties"].as_object().unwrap();
        for key in message.as_object().unwrap().keys() {
            assert!(
                properties.contains_key(key),
                "{key} not in {}",
                schema["title"]
            );
        }
    }

    #[test]
    fn messages_match_their_schemas() {
        let mut a = ReferenceAnswer::empty(3, AnswerStatus::Ok);
        a.flags = ReferenceAnswer::FLAG_HUMAN_POSITION;
        a.human_frame_position = [0.1, 0.2, 0.3];
        let asked = Asked {
            answer: a,
            round_trip_us: 42,
            received_ns: 0,
        };
        let message = answer(&asked);
        declared(&message, &answer_schema());
        assert_eq!(message["status"], "ok");
        assert_eq!(message["round_trip_us"], 42);
        assert_eq!(message["has_human_frame_position"], true);

        let message = stats(&MatcherStats::default());
        declared(&message, &stats_schema());
        assert_eq!(message["answers"]["no_match"], 0);

        let d = Decision {
            header: DecisionHeader::default(),
            entries: vec![DecisionEntry {
                human_track_id: 1,
                robot_track_id: 0,
                confidence: 0.5,
                status: AnswerStatus::NoMatch as u32,
                flags: 0,
                residual: 0.0,
            }],
        };
        let message = decision(&d);
        declared(&message, &decision_schema());
        assert_eq!(message["pairs"][0]["has_partner"], false);
        assert_eq!(message["pairs"][0]["status"], "no_match");
        assert_eq!(message["motion_estimated"], false);
    }
}
