#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! `vref scenes`: the real binary writing real files.

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

#[test]
fn same_arguments_give_the_same_file_and_stdout_matches_it() {
    let dir = tempfile::tempdir().unwrap();
    for out in ["a.jsonl", "b.jsonl"] {
        let run = vref(
            &[
                "scenes", "--preset", "moi", "--count", "4", "--seed", "7", "--out", out,
            ],
            dir.path(),
        );
        assert!(run.status.success(), "{}", stderr(&run));
        assert!(run.stdout.is_empty());
    }
    let a = std::fs::read(dir.path().join("a.jsonl")).unwrap();
    let b = std::fs::read(dir.path().join("b.jsonl")).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.iter().filter(|&&c| c == b'\n').count(), 4);
    let piped = vref(
        &["scenes", "--preset", "moi", "--count", "4", "--seed", "7"],
        dir.path(),
    );
    assert!(piped.status.success());
    assert_eq!(piped.stdout, a);
    // Only the two outputs: no temporary file left behind.
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["a.jsonl", "b.jsonl"]);
}

#[test]
fn generated_files_evaluate() {
    let dir = tempfile::tempdir().unwrap();
    let made = vref(
        &[
            "scenes",
            "--preset",
            "mrc",
            "--count",
            "3",
            "--seed",
            "1",
            "--out",
            "mrc.jsonl",
        ],
        dir.path(),
    );
    assert!(made.status.success(), "{}", stderr(&made));
    let eval = vref(&["eval", "--dataset", "mrc.jsonl", "--json"], dir.path());
    assert!(eval.status.success(), "{}", stderr(&eval));
    let lines: Vec<serde_json::Value> = String::from_utf8(eval.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert!(lines.len() >= 4, "one line per method expected");
    assert!(lines.iter().all(|l| l["scenes"] == 3));
}

#[test]
fn bad_arguments_exit_2_with_a_clear_message_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let zero = vref(
        &[
            "scenes", "--preset", "moi", "--count", "0", "--out", "x.jsonl",
        ],
        dir.path(),
    );
    assert_eq!(zero.status.code(), Some(2));
    assert!(stderr(&zero).contains("--count"), "{}", stderr(&zero));
    let unknown = vref(
        &[
            "scenes", "--preset", "kitchen", "--count", "1", "--out", "x.jsonl",
        ],
        dir.path(),
    );
    assert_eq!(unknown.status.code(), Some(2));
    let message = stderr(&unknown);
    assert!(
        message.contains("kitchen") && message.contains("moi, mrc"),
        "{message}"
    );
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn help_documents_every_flag() {
    let help = vref(&["scenes", "--help"], Path::new("."));
    assert!(help.status.success());
    let text = String::from_utf8(help.stdout).unwrap();
    for flag in ["--preset", "--count", "--seed", "--out", "moi", "mrc"] {
        assert!(text.contains(flag), "--help lacks {flag}:\n{text}");
    }
}

#[test]
fn rigid_scenes_have_exactly_the_asked_size_and_every_partner() {
    let dir = tempfile::tempdir().unwrap();
    let run = vref(
        &[
            "scenes",
            "--preset",
            "rigid",
            "--objects",
            "20",
            "--count",
            "2",
            "--out",
            "r.jsonl",
        ],
        dir.path(),
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let text = std::fs::read_to_string(dir.path().join("r.jsonl")).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    for line in &lines {
        assert_eq!(line["human"]["objects"].as_array().unwrap().len(), 20);
        assert_eq!(line["robot"]["objects"].as_array().unwrap().len(), 20);
        assert_eq!(line["ground_truth"].as_array().unwrap().len(), 20);
    }
    // And the live matcher tier finds them all.
    let eval = vref(
        &[
            "eval",
            "--dataset",
            "r.jsonl",
            "--method",
            "paper",
            "--tier",
            "live",
            "--json",
        ],
        dir.path(),
    );
    assert!(eval.status.success(), "{}", stderr(&eval));
    let report: serde_json::Value = serde_json::from_slice(&eval.stdout).unwrap();
    assert_eq!(report["tier"], "live");
    assert_eq!(report["accuracy"], 1.0);

    for bad in [
        &["scenes", "--preset", "rigid", "--count", "2"][..],
        &[
            "scenes",
            "--preset",
            "moi",
            "--objects",
            "5",
            "--count",
            "2",
        ][..],
        &[
            "scenes",
            "--preset",
            "rigid",
            "--objects",
            "1",
            "--count",
            "2",
        ][..],
    ] {
        let run = vref(bad, dir.path());
        assert_eq!(run.status.code(), Some(2), "{bad:?}: {}", stderr(&run));
        assert!(stderr(&run).contains("--objects") || stderr(&run).contains("objects"));
    }
}
