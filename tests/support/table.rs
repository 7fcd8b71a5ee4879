//! The six-object table scene of `vref inject --kind valid` as a dataset
//! file, for feeds that must publish a scene whose answers are known.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use vref_inject::{VALID_FEATURE_DIM, robot_id, valid_objects};
use vref_scene::Side;
use vref_testkit::Harness;
use vref_wire::ipc::IpcSettings;

/// The six-object table of `vref inject --kind valid`, as a dataset line:
/// each view's objects with their features, and the truth.
pub fn dataset() -> String {
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

/// A harness whose feeds can publish the table (`--source` is the third
/// value), with the ipc settings its configuration holds.
pub fn table_harness(tag: &str) -> (Harness, IpcSettings, String) {
    table_harness_with(tag, "", "")
}

/// Like [`table_harness`], with `matcher` lines added to the `[matcher]`
/// section and `ipc` lines to the `[ipc]` section.
pub fn table_harness_with(tag: &str, matcher: &str, ipc: &str) -> (Harness, IpcSettings, String) {
    let h = Harness::new(tag, &format!("{matcher}[matching]\nbeta = 0.01\n"));
    let text = std::fs::read_to_string(&h.config).unwrap();
    std::fs::write(
        &h.config,
        text.replacen("[ipc]\n", &format!("[ipc]\n{ipc}"), 1),
    )
    .unwrap();
    let scene = h.dir.path().join("table.jsonl");
    std::fs::write(&scene, dataset()).unwrap();
    let config = vref_config::Config::from_file(&h.config).unwrap();
    (h, config.ipc, format!("dataset:{}", scene.display()))
}
