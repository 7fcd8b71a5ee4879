#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! `vref eval --sweep`: the real binary generating, evaluating and drawing.

use std::path::Path;
use std::process::{Command, Output};

fn vref(args: &[&str], dir: &Path) -> Output {
    Command::new(vref_testkit::binary("vref"))
        .args(args)
        .current_dir(dir)
        .env_remove("VREF_CONFIG")
        .output()
        .unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

#[test]
fn a_tiny_sweep_draws_a_plot_and_prints_one_json_line_per_method_and_level() {
    let dir = tempfile::tempdir().unwrap();
    let run = vref(
        &[
            "eval",
            "--sweep",
            "depth-noise",
            "--preset",
            "moi",
            "--count",
            "2",
            "--levels",
            "0,2.5",
            "--method",
            "rrwm",
            "--method",
            "paper",
            "--json",
            "--out",
            "plot.png",
        ],
        dir.path(),
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let png = std::fs::read(dir.path().join("plot.png")).unwrap();
    assert_eq!(png[..8], PNG_SIGNATURE);

    let lines: Vec<serde_json::Value> = String::from_utf8(run.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let keys: Vec<(String, f64)> = lines
        .iter()
        .map(|l| {
            (
                l["method"].as_str().unwrap().to_owned(),
                l["level"].as_f64().unwrap(),
            )
        })
        .collect();
    let expected: Vec<(String, f64)> =
        [("rrwm", 0.0), ("paper", 0.0), ("rrwm", 2.5), ("paper", 2.5)]
            .iter()
            .map(|&(m, l)| (m.to_owned(), l))
            .collect();
    assert_eq!(keys, expected);
    for line in &lines {
        assert_eq!(line["sweep"], "depth-noise");
        assert_eq!(line["preset"], "moi");
        assert_eq!(line["scenes"], 2);
        for measure in ["accuracy", "precision", "recall"] {
            let value = line[measure].as_f64().unwrap();
            assert!((0.0..=1.0).contains(&value), "{measure} {value}");
        }
        assert_eq!(line.as_object().unwrap().len(), 8, "{line}");
    }
}

#[test]
fn without_json_a_table_lists_every_level_and_method() {
    let dir = tempfile::tempdir().unwrap();
    let run = vref(
        &[
            "eval",
            "--sweep",
            "feature-noise",
            "--preset",
            "mrc",
            "--count",
            "1",
            "--levels",
            "0,3",
            "--out",
            "f.png",
        ],
        dir.path(),
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let text = String::from_utf8(run.stdout).unwrap();
    assert!(
        text.starts_with("mrc, feature-noise: 1 scenes per level, seed 1\n"),
        "{text}"
    );
    // Header, then 2 levels x 6 methods.
    assert_eq!(text.lines().count(), 1 + 1 + 12, "{text}");
    assert!(dir.path().join("f.png").is_file());
}

#[test]
fn bad_sweeps_exit_2_naming_the_problem_and_draw_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = ["eval", "--sweep", "depth-noise", "--preset", "moi"];
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["--out", "p.png", "--dataset", "d.jsonl"],
            "cannot be used with",
        ),
        (vec![], "--out"),
        (vec!["--out", "p.png", "--levels", "0,-1"], "--levels"),
        (vec!["--out", "p.png", "--levels", "0,x"], "--levels"),
        (vec!["--out", "p.png", "--count", "0"], "--count"),
        (vec!["--out", "p.png", "--beta", "-1"], "beta"),
        (vec!["--out", "p.png", "--method", "rwm"], "rwm"),
    ];
    for (extra, needle) in cases {
        let args: Vec<&str> = sweep.iter().copied().chain(extra.iter().copied()).collect();
        let run = vref(&args, dir.path());
        assert_eq!(run.status.code(), Some(2), "{args:?}: {}", stderr(&run));
        assert!(stderr(&run).contains(needle), "{args:?}: {}", stderr(&run));
        assert!(run.stdout.is_empty());
    }
    let unknown = vref(
        &[
            "eval", "--sweep", "depth", "--preset", "moi", "--out", "p.png",
        ],
        dir.path(),
    );
    assert_eq!(unknown.status.code(), Some(2));
    assert!(stderr(&unknown).contains("depth-noise, feature-noise"));
    let preset = vref(
        &[
            "eval",
            "--sweep",
            "depth-noise",
            "--preset",
            "kitchen",
            "--out",
            "p.png",
        ],
        dir.path(),
    );
    assert_eq!(preset.status.code(), Some(2));
    assert!(stderr(&preset).contains("moi, mrc"));
    let stray = vref(
        &["eval", "--dataset", "d.jsonl", "--levels", "1"],
        dir.path(),
    );
    assert_eq!(stray.status.code(), Some(2), "{}", stderr(&stray));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn help_documents_the_sweep_flags() {
    let help = vref(&["eval", "--help"], Path::new("."));
    assert!(help.status.success());
    let text = String::from_utf8(help.stdout).unwrap();
    for flag in [
        "--sweep",
        "--preset",
        "--out",
        "--count",
        "--seed",
        "--levels",
        "depth-noise",
        "feature-noise",
        "[default: 30]",
        "[default: 1]",
    ] {
        assert!(text.contains(flag), "--help lacks {flag}:\n{text}");
    }
}
