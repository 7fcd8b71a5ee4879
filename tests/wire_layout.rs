//! docs/wire-layout.json is exactly what `vref wire-layout --json` prints:
//! the contract other languages check their types against
//! (clients/python/tests/test_layout.py) cannot fall behind the Rust types.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::time::Duration;

use support::{json_lines, vref};
use vref_testkit::repo_root;

const REGENERATE: &str = "run `vref wire-layout --json > docs/wire-layout.json` \
     (cargo run -p vref -- wire-layout --json > docs/wire-layout.json), then \
     align the Python types (clients/python/src/vref_client/wire.py) and docs/wire.md";

#[test]
fn the_committed_layout_is_what_vref_prints() {
    let printed = vref(&["wire-layout", "--json"], Duration::from_secs(30))
        .ok()
        .stdout;
    let path = repo_root().join("docs/wire-layout.json");
    let committed = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; {REGENERATE}", path.display()));
    let mut printed_lines = printed.lines();
    let mut committed_lines = committed.lines();
    for number in 1.. {
        match (printed_lines.next(), committed_lines.next()) {
            (None, None) => break,
            (p, c) => assert_eq!(
                p, c,
                "docs/wire-layout.json differs from the wire types at line {number}: {REGENERATE}"
            ),
        }
    }
}

#[test]
fn every_line_is_one_json_object_and_the_iceoryx2_version_is_the_locked_one() {
    let printed = vref(&["wire-layout", "--json"], Duration::from_secs(30))
        .ok()
        .stdout;
    let lines = json_lines(&printed);
    assert!(lines.iter().all(|l| l["record"].is_string()));
    let schema = &lines[0];
    assert_eq!(schema["record"], "schema");
    let lock = std::fs::read_to_string(repo_root().join("Cargo.lock")).unwrap();
    let locked = lock
        .split("[[package]]")
        .find(|p| p.contains("name = \"iceoryx2\"\n"))
        .and_then(|p| p.lines().find_map(|l| l.strip_prefix("version = ")))
        .unwrap()
        .trim_matches('"');
    assert_eq!(schema["iceoryx2"], locked);
}

#[test]
fn the_readable_layout_names_every_type_and_service() {
    let text = vref(
        &["wire-layout", "--namespace", "robot7"],
        Duration::from_secs(30),
    )
    .ok()
    .stdout;
    for name in [
        "vref::SnapshotHeader",
        "vref::ReferenceAnswer",
        "robot7/reference/answers",
        "robot7/matcher/stats",
    ] {
        assert!(text.contains(name), "{name} missing:\n{text}");
    }
}

#[test]
fn docs_wire_md_shows_every_type_as_printed() {
    let printed = vref(&["wire-layout", "--json"], Duration::from_secs(30))
        .ok()
        .stdout;
    let doc = std::fs::read_to_string(repo_root().join("docs/wire.md")).unwrap();
    for t in json_lines(&printed)
        .iter()
        .filter(|l| l["record"] == "type")
    {
        let heading = format!(
            "`{}`: {} bytes, align {}",
            t["type_name"].as_str().unwrap(),
            t["size"],
            t["align"]
        );
        let start = doc.find(&heading).unwrap_or_else(|| {
            panic!("docs/wire.md lacks `{heading}`: update its struct blocks to the layout")
        });
        let block = &doc[start..];
        let block = &block[..block.find("};").unwrap()];
        let lines: Vec<&str> = block.lines().filter(|l| l.contains("// offset")).collect();
        let fields = t["fields"].as_array().unwrap();
        assert_eq!(lines.len(), fields.len(), "docs/wire.md, {heading}");
        for (line, field) in lines.iter().zip(fields) {
            let name = field["name"].as_str().unwrap();
            let declared = line.split("//").next().unwrap();
            assert!(
                declared.contains(&format!(" {name};")) || declared.contains(&format!(" {name}[")),
                "docs/wire.md, {heading}: `{line}` is not field {name}"
            );
            assert!(
                line.ends_with(&format!("// offset {}", field["offset"])),
                "docs/wire.md, {heading}: `{line}`, expected offset {}",
                field["offset"]
            );
        }
    }
}

/// Issue 40, case 9: a client written from the layout alone had to guess
/// iceoryx2's file prefix, the grammar of field types and when to notify.
/// The schema record states them, and every field's type follows the
/// stated grammar (a record named in `[T; N]` is one of the file's types).
#[test]
fn the_layout_states_the_prefix_the_type_grammar_and_the_event_rules() {
    let printed = vref(&["wire-layout", "--json"], Duration::from_secs(30))
        .ok()
        .stdout;
    let lines = json_lines(&printed);
    let schema = &lines[0];
    assert_eq!(schema["iceoryx2_prefix"], "vref_");
    let grammar = schema["type_grammar"].as_str().unwrap();
    assert!(grammar.contains("[T; N]"), "{grammar}");
    let rules: Vec<&str> = schema["event_rules"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r.as_str().unwrap())
        .collect();
    for needed in ["request_event", "notifier_dead_event", "EventId", "iox2_"] {
        assert!(
            rules.iter().any(|r| r.contains(needed)),
            "{needed}: {rules:?}"
        );
    }
    // ... and how to fill the fields whose values are rules, not data
    // (what tools/layout-client.py follows).
    let fields: Vec<&str> = schema["field_rules"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r.as_str().unwrap())
        .collect();
    for needed in [
        "schema_version",
        "Unix epoch",
        "sequence",
        "object_count",
        "feature_dim",
        "request_id",
        "QueryKind",
        "AnswerStatus",
    ] {
        assert!(
            fields.iter().any(|r| r.contains(needed)),
            "{needed}: {fields:?}"
        );
    }
    let types: Vec<&serde_json::Value> = lines.iter().filter(|l| l["record"] == "type").collect();
    let names: Vec<&str> = types.iter().map(|t| t["name"].as_str().unwrap()).collect();
    let base = ["u8", "u16", "u32", "u64", "i32", "i64", "f32", "f64"];
    for t in &types {
        for field in t["fields"].as_array().unwrap() {
            let ty = field["type"].as_str().unwrap();
            let element = match ty.strip_prefix('[').and_then(|r| r.strip_suffix(']')) {
                Some(inner) => {
                    let (element, count) = inner.split_once("; ").unwrap();
                    assert!(count.parse::<usize>().is_ok(), "{ty}");
                    element
                }
                None => ty,
            };
            assert!(
                base.contains(&element) || names.contains(&element),
                "{}.{}: {ty} is outside the stated grammar",
                t["name"],
                field["name"]
            );
        }
    }
    for service in lines.iter().filter(|l| l["pattern"] == "event") {
        assert!(service["qos"]["notifier_dead_event"].is_u64(), "{service}");
    }
}
