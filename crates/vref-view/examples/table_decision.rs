//! The six-object table of the system tests, with the decision the
//! matcher will publish for it: until the matcher publishes its decision
//! (issue 14), this shows what `vref view` draws with one.
//!
//! ```sh
//! cargo run -p vref-view --example table_decision -- CONFIG TABLE.jsonl
//! ```
//!
//! writes the table as a dataset file TABLE.jsonl (for the feeds:
//! `--source dataset:TABLE.jsonl`), then publishes, every 100 ms until
//! SIGINT, the true decision (each human object matched to its robot
//! object, confidence 0.95, with the motion between the views) and a ray
//! from the headset at human object 2, under CONFIG's `[ipc]`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::time::Duration;

use vref_inject::{VALID_FEATURE_DIM, robot_id, valid_objects};
use vref_scene::Side;
use vref_wire::ipc::{DecisionPublisher, GesturePublisher, create_node};
use vref_wire::{AnswerStatus, DecisionEntry, DecisionHeader};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [config, dataset] = args.as_slice() else {
        eprintln!("usage: table_decision CONFIG TABLE.jsonl");
        std::process::exit(2);
    };
    std::fs::write(dataset, table()).unwrap();
    let config = vref_config::Config::from_file(std::path::Path::new(config)).unwrap();
    let ipc = config.ipc;
    let node = create_node(&ipc, "table-decision").unwrap();
    let mut decisions = DecisionPublisher::new(&node, &ipc).unwrap();
    let mut rays = GesturePublisher::new(&node, &ipc).unwrap();
    let humans = valid_objects(Side::Human);
    let mut solve = 0;
    while vref_wire::ipc::nap(&node, Duration::from_millis(100)) {
        solve += 1;
        let header = DecisionHeader {
            solve_index: solve,
            // The table's robot view is its human view turned a quarter
            // about the vertical and shifted (vref-inject's scene).
            rotation: [0.0, 0.0, 1.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0],
            translation: [-0.9, 0.02, 1.0],
            flags: DecisionHeader::FLAG_MOTION,
            method: *b"rigid\0\0\0\0\0\0\0\0\0\0\0",
            ..DecisionHeader::default()
        };
        decisions
            .publish(header, humans.len(), |i| DecisionEntry {
                human_track_id: humans[i].track_id,
                robot_track_id: robot_id(humans[i].track_id),
                confidence: 0.95,
                status: AnswerStatus::Ok as u32,
                flags: DecisionEntry::FLAG_PARTNER,
                residual: 0.0,
            })
            .unwrap();
        rays.publish([0.0; 3], humans[1].position, 0.05, 0.9)
            .unwrap();
    }
}

/// The table as a dataset line (tests/support/table.rs writes the same).
fn table() -> String {
    let view = |side| -> Vec<serde_json::Value> {
        valid_objects(side)
            .iter()
            .map(|o| {
                serde_json::json!({
                    "id": o.track_id,
                    "position": o.position.map(f64::from),
                    "feature": o.feature[..VALID_FEATURE_DIM].to_vec(),
                })
            })
            .collect()
    };
    let truth: Vec<_> = valid_objects(Side::Human)
        .iter()
        .map(|o| [o.track_id, robot_id(o.track_id)])
        .collect();
    let line = serde_json::json!({
        "name": "table",
        "robot": {"objects": view(Side::Robot)},
        "human": {"objects": view(Side::Human)},
        "ground_truth": truth,
    });
    format!("{line}\n")
}
