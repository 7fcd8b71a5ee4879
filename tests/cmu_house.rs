//! The published CMU House protocol, end to end through the `vref` binary:
//! 30 vs 30 landmarks, Delaunay edges, no node term, beta = 2500 pixels^2.
//! Reference figures (ALGORITHMS.md): SM 1.0 / .914 / .637 and RRWM
//! 1.0 / 1.0 / .997 mean accuracy at frame gaps 0 / 50 / 90.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::HashMap;
use std::time::Duration;

use support::{cmu_house_dir, json_lines, vref};

/// Imports gap `gap` and returns accuracy by method name.
fn accuracy_at_gap(gap: usize) -> HashMap<String, (f64, u64)> {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join(format!("house-gap{gap}.jsonl"));
    let data = cmu_house_dir();
    let (file_s, data_s, gap_s) = (
        file.to_str().unwrap(),
        data.to_str().unwrap(),
        gap.to_string(),
    );
    vref(
        &[
            "import",
            "cmu-house",
            data_s,
            "--gap",
            &gap_s,
            "--delaunay",
            "--out",
            file_s,
        ],
        Duration::from_secs(60),
    )
    .ok();
    let run = vref(
        &[
            "eval",
            "--dataset",
            file_s,
            "--method",
            "sm",
            "--method",
            "rrwm",
            "--beta",
            "2500",
            "--json",
        ],
        Duration::from_secs(300),
    )
    .ok();
    json_lines(&run.stdout)
        .into_iter()
        .map(|v| {
            let method = v["method"].as_str().unwrap().to_owned();
            (
                method,
                (
                    v["accuracy"].as_f64().unwrap(),
                    v["scenes"].as_u64().unwrap(),
                ),
            )
        })
        .collect()
}

#[test]
fn gap_0_every_frame_matched_to_itself() {
    let acc = accuracy_at_gap(0);
    assert_eq!(acc["rrwm"], (1.0, 111));
    assert_eq!(acc["sm"].0, 1.0);
}

#[test]
fn gap_50_sm_near_published() {
    let acc = accuracy_at_gap(50);
    assert_eq!(acc["sm"].1, 61);
    let sm = acc["sm"].0;
    assert!(
        (sm - 0.914).abs() <= 0.02,
        "sm accuracy {sm}, published 0.914"
    );
    assert!(acc["rrwm"].0 >= 0.99, "rrwm accuracy {}", acc["rrwm"].0);
}

#[test]
fn gap_90_rrwm_and_sm_near_published() {
    let acc = accuracy_at_gap(90);
    assert_eq!(acc["rrwm"].1, 21);
    let (sm, rrwm) = (acc["sm"].0, acc["rrwm"].0);
    assert!(rrwm >= 0.99, "rrwm accuracy {rrwm}, published 0.997");
    assert!(
        (sm - 0.637).abs() <= 0.02,
        "sm accuracy {sm}, published 0.637"
    );
}
