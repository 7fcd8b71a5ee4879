//! `vref wire-layout`: the wire contract for other languages, printed from
//! the types and the service catalogue themselves (vref_wire::layout,
//! vref_wire::ipc::catalogue). docs/wire-layout.json is this command's
//! `--json` output, kept equal by a test.

use serde_json::{Value, json};
use vref_config::Config;
use vref_logging::exit::{Blame, Failure};
use vref_reference::RejectReason;
use vref_wire::ipc::{IpcSettings, Pattern, catalogue};
use vref_wire::layout::{Codes, codes, constants, wire_types};

use crate::cli::WireLayoutArgs;
use crate::stdout;
use crate::table::Table;

/// The iceoryx2 version every process sharing the services must run
/// (Cargo.toml pins it exactly; a test checks Cargo.lock agrees).
pub const ICEORYX2_VERSION: &str = "0.10.0";

pub fn run(args: &WireLayoutArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let mut ipc = config.ipc;
    if let Some(namespace) = &args.namespace {
        ipc.namespace.clone_from(namespace);
    }
    let text = if args.json {
        lines(&ipc)
            .iter()
            .map(|line| format!("{line}\n"))
            .collect::<String>()
    } else {
        readable(&ipc)
    };
    stdout::print(&text)
}

/// How a field's `type` is written.
const TYPE_GRAMMAR: &str = "u8, u16, u32, u64, i32, i64, f32 or f64 (little-endian, C layout), \
    or [T; N]: N values of T in a row, where T is one of those or the `name` of another \
    record of kind type (e.g. [Alternative; 3]); offsets and sizes are in bytes";

/// When a process notifies which event service.
const EVENT_RULES: [&str; 4] = [
    "after each sample sent on a publish_subscribe service, notify the event service its `event` names (notify(), EventId 0)",
    "after each request sent on a request_response service, notify the service its `request_event` names; the server notifies `response_event` after it sent answers, and a waiting client listens there",
    "qos.notifier_dead_event is an iceoryx2 EventId value: what a listener receives when a notifier's process died",
    "every process opens or creates the services with exactly the qos given here, under iceoryx2's file prefix `iceoryx2_prefix` (iceoryx2's own default, iox2_, never meets the services)",
];

/// How a sender fills the fields whose values are rules rather than data,
/// and what a reader takes from an answer: what a client written from this
/// file alone needs beyond the layout to be answered (issue 40).
const FIELD_RULES: [&str; 10] = [
    "every `schema_version` field holds the schema record's `schema_version`; `reserved` fields hold 0",
    "`timestamp_ns` is the capture time in nanoseconds since the Unix epoch (the sender's clock, which must agree with the matcher's): the matcher refuses a message older than its [matcher] max_capture_age_ms (default 10 s) or ahead of its clock by more than max_clock_skew_ms (default 100 ms), and an answer resting on a snapshot older than stale_after_ms (default 500 ms) is `stale`, so a sender keeps publishing",
    "`session` is a number the sender picks anew each time it starts; `sequence` counts its messages on a service from 1 and must grow within a session",
    "SnapshotHeader: `side` is the SideCode of the service (robot on robot/snapshot, human on human/snapshot); `object_count` is the number of ObjectEntry in the sample's slice; `feature_dim` is how many leading `feature` values are used (at most MAX_FEATURE_DIM, the same on both sides; the rest 0); `frame_name` is UTF-8 padded with 0 bytes; `up` is the view's up vector with flag `up` set, else zeros and no flag",
    "ObjectEntry: `track_id` is unique within its snapshot and names the object in answers; `position` is in metres in the view's camera frame; `position_sigma` is the position's standard deviation per axis in metres (>= 0; 0: not stated); `feature` is an appearance description compared between the sides",
    "PointingRay: `origin` and `direction` in the human view's camera frame (direction non-zero), `cone_half_angle` in radians in (0, pi/2], `confidence` in [0, 1]",
    "ReferenceQuery: `request_id` is the client's own number, echoed by the answer; `kind` is a QueryKind: human_object asks for the robot object that the human snapshot's object `human_object_id` is, ray for the object the ray (`ray_origin`, `ray_direction`, `cone_half_angle`, human camera frame) points at, latest_gesture for the one the latest PointingRay points at; fields a kind does not use hold 0",
    "ReferenceAnswer: `status` is an AnswerStatus; with ok (an answer to act on) or ambiguous, `robot_track_id` names the robot snapshot's object and `position` is its position in the robot camera frame; `alternative_count` of `alternatives` are the next candidates",
    "answers come only once both a robot and a human snapshot were accepted and solved: until then, and for a query whose object is not in the human snapshot, the status says why (not_ready, bad_request)",
    "a client is answered at most [matcher] max_queries_per_client_hz times a second (default 2000, in bursts of a tenth of a second's worth): queries beyond it are dropped unanswered (and counted)",
];

/// The matcher's reject reasons: the index of `MatcherStats.rejected`,
/// and the value of `ReferenceAnswer.refusal`.
fn reject_reasons() -> Codes {
    Codes {
        name: "RejectReason",
        used_in: vec!["MatcherStats.rejected", "ReferenceAnswer.refusal"],
        kind: "index",
        values: RejectReason::ALL
            .into_iter()
            .map(|r| vref_wire::layout::Code {
                name: r.name(),
                value: r as u32,
            })
            .collect(),
    }
}

fn all_codes() -> Vec<Codes> {
    let mut all = codes();
    all.push(reject_reasons());
    all
}

/// One JSON object per line: the schema and constants, then each type,
/// each set of codes, each service.
pub fn lines(ipc: &IpcSettings) -> Vec<Value> {
    let constants: serde_json::Map<String, Value> = constants()
        .into_iter()
        .map(|c| (c.name.to_owned(), json!(c.value)))
        .collect();
    let mut lines = vec![json!({
        "record": "schema",
        "schema_version": vref_wire::SCHEMA_VERSION,
        "iceoryx2": ICEORYX2_VERSION,
        "namespace": ipc.namespace,
        "max_clients": ipc.max_clients,
        "max_subscribers": ipc.max_subscribers,
        "initial_objects": ipc.initial_objects,
        "constants": constants,
        // What a client written from this file alone had to guess
        // (issue 40, case 9).
        "iceoryx2_prefix": ipc.prefix,
        "type_grammar": TYPE_GRAMMAR,
        "event_rules": EVENT_RULES,
        "field_rules": FIELD_RULES,
    })];
    let tagged = |record: &str, value: Value| {
        let mut value = value;
        if let Value::Object(map) = &mut value {
            map.insert("record".to_owned(), json!(record));
        }
        value
    };
    for t in wire_types() {
        lines.push(tagged("type", json!(t)));
    }
    for c in all_codes() {
        lines.push(tagged("codes", json!(c)));
    }
    for s in catalogue(ipc) {
        lines.push(tagged("service", json!(s)));
    }
    lines
}

fn readable(ipc: &IpcSettings) -> String {
    let mut out = format!(
        "vref wire schema {}, iceoryx2 {ICEORYX2_VERSION}, namespace {}\n",
        vref_wire::SCHEMA_VERSION,
        ipc.namespace
    );
    for t in wire_types() {
        out += &format!(
            "\n{} (type name {}, {} bytes, align {})\n",
            t.name, t.type_name, t.size, t.align
        );
        let mut table = Table::new(&["field", "offset", "size", "type"]);
        for f in &t.fields {
            table.row(vec![
                f.name.to_owned(),
                f.offset.to_string(),
                f.size.to_string(),
                f.ty.clone(),
            ]);
        }
        out += &table.to_string();
    }
    out += "\n";
    for c in all_codes() {
        let values: Vec<String> = c
            .values
            .iter()
            .map(|v| format!("{} = {}", v.name, v.value))
            .collect();
        out += &format!("{} ({}): {}\n", c.name, c.kind, values.join(", "));
    }
    out += "\nservices (their settings: --json)\n";
    for s in catalogue(ipc) {
        let line = match &s.pattern {
            Pattern::PublishSubscribe {
                payload,
                user_header,
                event,
                ..
            } => {
                let mut line = if payload.variant == "dynamic" {
                    format!("publish-subscribe [{}]", payload.type_name)
                } else {
                    format!("publish-subscribe {}", payload.type_name)
                };
                if let Some(h) = user_header {
                    line += &format!(" with user header {}", h.type_name);
                }
                match event {
                    Some(e) => line += &format!("; event {e}"),
                    None => line += "; no event (readers poll)",
                }
                line
            }
            Pattern::RequestResponse {
                request,
                response,
                request_event,
                response_event,
                ..
            } => format!(
                "request-response {} -> {}; events {request_event} (requests), {response_event} (answers)",
                request.type_name, response.type_name
            ),
            Pattern::Event {
                notifier, listener, ..
            } => format!("event: notified by {notifier}; listener {listener}"),
        };
        out += &format!("  {}: {line}\n", s.name);
    }
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    #[test]
    fn every_line_is_a_tagged_object() {
        let lines = lines(&IpcSettings::default());
        assert_eq!(lines[0]["record"], "schema");
        assert_eq!(lines[0]["schema_version"], vref_wire::SCHEMA_VERSION);
        for line in &lines {
            assert!(line["record"].is_string(), "{line}");
        }
        let services = lines.iter().filter(|l| l["record"] == "service").count();
        assert_eq!(services, catalogue(&IpcSettings::default()).len());
    }

    #[test]
    fn reject_reasons_fit_the_stats_slots() {
        let reasons = reject_reasons();
        assert!(reasons.values.len() <= vref_wire::MAX_REJECT_REASONS);
        for (index, code) in reasons.values.iter().enumerate() {
            assert_eq!(code.value as usize, index, "{}", code.name);
        }
    }
}
