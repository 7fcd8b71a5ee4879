#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! `vref scenes`: the real binary writing real files.

use std::path::Path;
use std::process::{Command, Output};

fn vref(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vref"))
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
