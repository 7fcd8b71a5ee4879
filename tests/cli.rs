//! The `vref` command line as a user meets it: help, output contracts,
//! exit codes and error messages for bad input.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;
use std::time::Duration;

use support::{cmu_house_dir, json_lines, vref};
use vref_testkit::repo_root;

const LIMIT: Duration = Duration::from_secs(60);

/// A small valid scene: a triangle seen twice, robot ids shuffled.
const SCENE: &str = r#"{"name":"tri","robot":{"objects":[{"id":7,"position":[0.5,0.1,1.0],"feature":[0,1]},{"id":3,"position":[0,0,1],"feature":[1,0]},{"id":9,"position":[0,0.3,1.2],"feature":[1,1]}]},"human":{"objects":[{"id":1,"position":[0,0,1],"feature":[1,0]},{"id":2,"position":[0.5,0.1,1.0],"feature":[0,1]},{"id":4,"position":[0,0.3,1.2],"feature":[1,1]}]},"ground_truth":[[1,3],[2,7],[4,9]]}"#;

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_owned()
}

#[test]
fn every_command_has_help() {
    for args in [
        vec!["--help"],
        vec!["eval", "--help"],
        vec!["import", "--help"],
        vec!["import", "cmu-house", "--help"],
        vec!["import", "bop", "--help"],
        vec!["bench", "perception", "--help"],
        vec!["viz", "--help"],
        vec!["config", "check", "--help"],
    ] {
        let run = vref(&args, LIMIT).ok();
        assert!(run.stdout.contains("Usage:"), "{args:?}: {}", run.stdout);
    }
    let run = vref(&["eval", "--help"], LIMIT).ok();
    for flag in ["--dataset", "--method", "--beta", "--json", "--config"] {
        assert!(run.stdout.contains(flag), "eval --help lacks {flag}");
    }
}

#[test]
fn every_service_states_its_exit_codes_in_its_help() {
    for service in [
        "vref-matcher",
        "vref-perception-feed",
        "vref-gesture-feed",
        "vref-bridge",
    ] {
        let run = support::vref_at(&vref_testkit::binary(service), &["--help"], LIMIT).ok();
        for code in ["Exit codes: 0", "1 failure while running", "2 bad"] {
            assert!(
                run.stdout.contains(code),
                "{service} --help lacks `{code}`:\n{}",
                run.stdout
            );
        }
    }
}

#[test]
fn eval_json_has_one_object_per_method_with_the_contract_fields() {
    let dir = tempfile::tempdir().unwrap();
    let data = write(dir.path(), "tri.jsonl", &format!("{SCENE}\n"));
    let run = vref(
        &["eval", "--dataset", &data, "--json", "--beta", "0.01"],
        LIMIT,
    )
    .ok();
    let lines = json_lines(&run.stdout);
    let methods: Vec<&str> = lines
        .iter()
        .map(|v| v["method"].as_str().unwrap())
        .collect();
    assert_eq!(
        methods,
        ["appearance", "sm", "rrwm", "paper", "rigid", "clipper"]
    );
    for v in &lines {
        assert_eq!(v["dataset"], data.as_str());
        assert_eq!(v["scenes"], 1);
        for field in ["accuracy", "precision", "recall", "mean_solve_us", "ece"] {
            assert!(v[field].as_f64().is_some(), "{field} missing in {v}");
        }
    }
    // Distinct features on a rigid triangle: appearance alone is right.
    assert_eq!(lines[0]["accuracy"], 1.0);
}

#[test]
fn eval_table_names_every_requested_method() {
    let dir = tempfile::tempdir().unwrap();
    let data = write(dir.path(), "tri.jsonl", &format!("{SCENE}\n"));
    let run = vref(
        &[
            "eval",
            "--dataset",
            &data,
            "--method",
            "paper",
            "--method",
            "sm",
        ],
        LIMIT,
    )
    .ok();
    assert!(run.stdout.contains("paper") && run.stdout.contains("sm"));
    assert!(!run.stdout.contains("rrwm"));
    assert!(run.stdout.contains("1 scenes"));
}

#[test]
fn malformed_dataset_line_is_reported_by_line_and_field_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let broken = SCENE.replace("[0,0.3,1.2]", "[0,\"x\",1.2]");
    let data = write(dir.path(), "bad.jsonl", &format!("{SCENE}\n\n{broken}\n"));
    let run = vref(&["eval", "--dataset", &data], LIMIT);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(run.stderr.contains("line 3"), "{}", run.stderr);
    assert!(
        run.stderr.contains("robot.objects[2].position"),
        "{}",
        run.stderr
    );
    assert!(run.stdout.is_empty());
}

#[test]
fn invalid_scene_is_reported_with_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let duplicate = SCENE.replace("\"id\":9", "\"id\":7");
    let data = write(dir.path(), "dup.jsonl", &format!("{duplicate}\n"));
    let run = vref(&["eval", "--dataset", &data], LIMIT);
    assert_eq!(run.code, Some(2));
    assert!(
        run.stderr.contains("line 1") && run.stderr.contains("\"tri\""),
        "{}",
        run.stderr
    );
    assert!(
        run.stderr.contains("object id 7 appears more than once"),
        "{}",
        run.stderr
    );
}

#[test]
fn bad_arguments_exit_2_with_a_reason() {
    let dir = tempfile::tempdir().unwrap();
    let data = write(dir.path(), "tri.jsonl", &format!("{SCENE}\n"));
    let empty = write(dir.path(), "empty.jsonl", "\n");
    // Paths of this test's own: "/nonexistent" is a real, empty folder on
    // some machines (a system user's home).
    let bop_missing = format!("bop:{}", dir.path().join("missing").display());
    std::fs::create_dir(dir.path().join("no-scenes")).unwrap();
    let bop_empty = format!("bop:{}", dir.path().join("no-scenes").display());
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["eval", "--dataset", &data, "--method", "rwm"],
            "unknown method `rwm`",
        ),
        (vec!["eval", "--dataset", &data, "--beta", "-1"], "beta"),
        (
            vec!["eval", "--dataset", "/nonexistent/x.jsonl"],
            "/nonexistent/x.jsonl",
        ),
        (vec!["eval", "--dataset", &empty], "no scenes"),
        (
            vec!["import", "cmu-house", "/nonexistent", "--gap", "1"],
            "no frames",
        ),
        // The reason under the setup error, not only its name; refused
        // before any service starts.
        (
            vec!["bench", "remote", "--objects", "2", "--duration", "1s"],
            "lets both views see at least 3 objects",
        ),
        (vec!["demo", "--source", &bop_missing], &bop_missing[4..]),
        (
            vec!["demo", "--source", &bop_empty],
            "no scene folders found",
        ),
    ];
    for (args, reason) in cases {
        let run = vref(&args, LIMIT);
        assert_eq!(run.code, Some(2), "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains(reason), "{args:?}: {}", run.stderr);
    }
}

#[test]
fn import_refuses_a_gap_beyond_the_sequence_and_a_bad_keep() {
    let data = cmu_house_dir();
    let data = data.to_str().unwrap();
    let run = vref(&["import", "cmu-house", data, "--gap", "111"], LIMIT);
    assert_eq!(run.code, Some(2));
    assert!(
        run.stderr
            .contains("frame gap 111 leaves no pair among 111 frames"),
        "{}",
        run.stderr
    );
    let run = vref(
        &["import", "cmu-house", data, "--gap", "1", "--keep", "31"],
        LIMIT,
    );
    assert_eq!(run.code, Some(2));
    assert!(
        run.stderr.contains("cannot keep 31 landmarks"),
        "{}",
        run.stderr
    );
}

#[test]
fn import_with_keep_leaves_objects_without_partner_and_is_reproducible() {
    let data = cmu_house_dir();
    let data = data.to_str().unwrap();
    let args = |seed: &'static str| {
        vec![
            "import",
            "cmu-house",
            data,
            "--gap",
            "10",
            "--keep",
            "25",
            "--features",
            "--seed",
            seed,
        ]
    };
    let a = vref(&args("7"), LIMIT).ok().stdout;
    let b = vref(&args("7"), LIMIT).ok().stdout;
    let c = vref(&args("8"), LIMIT).ok().stdout;
    assert_eq!(a, b, "same seed must give the same bytes");
    assert_ne!(a, c, "another seed must choose other landmarks");
    let scenes = json_lines(&a);
    assert_eq!(scenes.len(), 101);
    let mut unpartnered = 0;
    for s in &scenes {
        assert_eq!(s["human"]["objects"].as_array().unwrap().len(), 25);
        assert_eq!(s["robot"]["objects"].as_array().unwrap().len(), 25);
        assert_eq!(
            s["human"]["objects"][0]["feature"]
                .as_array()
                .unwrap()
                .len(),
            60
        );
        unpartnered += 25 - s["ground_truth"].as_array().unwrap().len();
    }
    assert!(unpartnered > 0);
}

#[test]
fn config_check_accepts_the_shipped_file_and_names_an_unknown_key() {
    let shipped = repo_root().join("config/vref.toml");
    let run = vref(&["config", "check", shipped.to_str().unwrap()], LIMIT).ok();
    assert!(run.stdout.contains(": ok"));

    let dir = tempfile::tempdir().unwrap();
    let typo = write(
        dir.path(),
        "typo.toml",
        "[matching]\nbeta = 0.01\nbetta = 2\n",
    );
    let run = vref(&["config", "check", &typo], LIMIT);
    assert_eq!(run.code, Some(2));
    assert!(run.stderr.contains("betta"), "{}", run.stderr);

    let bad = write(dir.path(), "bad.toml", "[matching.rrwm]\nc = 2.0\n");
    let run = vref(&["config", "check", &bad], LIMIT);
    assert_eq!(run.code, Some(2));
    assert!(run.stderr.contains("rrwm.c"), "{}", run.stderr);

    // A method that cannot solve its capacity within the freshness budget.
    let slow = write(
        dir.path(),
        "slow.toml",
        "[matcher]\nmethod = \"paper\"\ntier = \"exact\"\n",
    );
    let run = vref(&["config", "check", &slow], LIMIT);
    assert_eq!(run.code, Some(2));
    for part in ["freshness budget of 250 ms", "[scene] capacity to 87"] {
        assert!(run.stderr.contains(part), "{part}: {}", run.stderr);
    }
}

#[test]
fn config_check_refuses_a_bad_tier_naming_it_and_so_does_the_matcher() {
    let dir = tempfile::tempdir().unwrap();
    let bad = write(dir.path(), "tier.toml", "[matcher]\ntier = \"fastest\"\n");
    let run = vref(&["config", "check", &bad], LIMIT);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    for part in ["[matcher] tier", "fastest", "exact or live"] {
        assert!(run.stderr.contains(part), "{part}: {}", run.stderr);
    }
    // The matcher refuses the same file as bad configuration (2), at once.
    let matcher = vref_testkit::binary("vref-matcher");
    let out = std::process::Command::new(matcher)
        .args(["--config", &bad])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("tier"));
}

/// Issue 41: a misspelt `VREF_SIMD` once meant "every path the CPU has";
/// the CLI and the matcher now refuse it at start (2), naming it.
#[test]
fn an_unknown_simd_cap_is_refused_naming_it() {
    let vref = &vref_testkit::binary("vref");
    let config = repo_root().join("config/vref.toml");
    let config = config.to_str().unwrap();
    let run = support::vref_with(
        vref,
        &["config", "check", config],
        &[("VREF_SIMD", "avx-512")],
        LIMIT,
    );
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(
        run.stderr.contains("VREF_SIMD=\"avx-512\""),
        "{}",
        run.stderr
    );
    let ok = support::vref_with(
        vref,
        &["config", "check", config],
        &[("VREF_SIMD", "avx512")],
        LIMIT,
    );
    assert_eq!(ok.code, Some(0), "{}", ok.stderr);
    // The limit is a hang guard: the matcher refuses before it starts.
    let matcher = vref.with_file_name("vref-matcher");
    let run = support::vref_with(&matcher, &[], &[("VREF_SIMD", "sse")], LIMIT);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(run.stderr.contains("VREF_SIMD"), "{}", run.stderr);
}

/// Issue 40, case 7: `vref config check` accepted these, and the matcher
/// then exited 1 (for the root path saying only `ResourceCreationFailed`),
/// or, with a relative root path, ran with iceoryx2's files in its working
/// directory. Both now refuse each as bad configuration (2), naming it.
#[test]
fn config_check_and_the_matcher_refuse_bad_ipc_settings_and_presets() {
    let dir = tempfile::tempdir().unwrap();
    let long_root = format!("/tmp/{}", "r".repeat(100));
    let cases = [
        (
            "slash",
            "[ipc]\nprefix = \"a/b_\"\n".to_owned(),
            "`/` is not allowed",
        ),
        (
            "long",
            format!("[ipc]\nprefix = \"{}\"\n", "p".repeat(300)),
            "at most 32",
        ),
        (
            "root",
            format!("[ipc]\nroot_path = \"{long_root}\"\n"),
            "Unix socket path",
        ),
        (
            "relative",
            "[ipc]\nroot_path = \"iox\"\n".to_owned(),
            "must be absolute",
        ),
        ("preset", "[feeds]\npreset = \"nope\"\n".to_owned(), "nope"),
    ];
    let matcher = vref_testkit::binary("vref-matcher");
    for (name, text, says) in cases {
        let file = write(dir.path(), &format!("{name}.toml"), &text);
        let run = vref(&["config", "check", &file], LIMIT);
        assert_eq!(run.code, Some(2), "{name}: {}", run.stderr);
        assert!(run.stderr.contains(says), "{name}: {}", run.stderr);
        let mut child = std::process::Command::new(&matcher)
            .args(["--config", &file])
            .current_dir(dir.path())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let status = vref_testkit::exit_within(&mut child, Duration::from_secs(10), || {
            format!("{name}: the matcher with the bad configuration")
        });
        let mut stderr = String::new();
        std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
        assert_eq!(status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.contains(says), "{name}: {stderr}");
    }
    assert!(
        !dir.path().join("iox").exists(),
        "no folder in the working directory"
    );
}

#[test]
fn durations_take_one_form_with_a_unit_and_bad_ones_are_named() {
    for (args, says) in [
        (&["demo", "--duration", "20"][..], "has no unit"),
        (&["soak", "--duration", "soon"], "not a duration"),
        (
            &["query", "--latest-gesture", "--timeout", "5 parsecs"],
            "unknown unit",
        ),
        (&["bench", "query", "--duration", "0s"], "positive"),
        (&["record", "--out", "x.vrec", "--duration=-1s"], "positive"),
    ] {
        let run = vref(args, LIMIT);
        assert_eq!(run.code, Some(2), "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains(says), "{args:?}: {}", run.stderr);
    }
    // The former millisecond flag still works, but not beside the new one.
    let run = vref(
        &[
            "query",
            "--latest-gesture",
            "--timeout",
            "1s",
            "--timeout-ms",
            "5",
        ],
        LIMIT,
    );
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(run.stderr.contains("cannot be used with"), "{}", run.stderr);
    let help = vref(&["query", "--help"], LIMIT).ok();
    for part in [
        "--timeout <D>",
        "Exit codes",
        "3 bad_request",
        "4 not_ready",
        "5 stale",
    ] {
        assert!(help.stdout.contains(part), "query --help lacks {part}");
    }
}

/// The text of `vref eval --answers` for `methods` on `scenes` in `tier`,
/// run with `VREF_SIMD=cap`.
fn answers_under_cap(
    dir: &std::path::Path,
    scenes: &str,
    methods: &[&str],
    tier: &str,
    cap: &str,
) -> String {
    let out = dir.join(format!("answers-{cap}.jsonl"));
    let out = out.to_str().unwrap().to_owned();
    let mut args = vec![
        "eval",
        "--dataset",
        scenes,
        "--tier",
        tier,
        "--answers",
        &out,
    ];
    for method in methods {
        args.extend(["--method", method]);
    }
    support::vref_with(
        &vref_testkit::binary("vref"),
        &args,
        &[("VREF_SIMD", cap)],
        Duration::from_secs(120),
    )
    .ok();
    std::fs::read_to_string(&out).unwrap()
}

/// `vref scenes ARGS` written to a file in `dir`; its path.
fn scenes_file(dir: &Path, args: &[&str]) -> String {
    let out = dir.join("scenes.jsonl");
    let out = out.to_str().unwrap().to_owned();
    let mut all = vec!["scenes"];
    all.extend_from_slice(args);
    all.extend(["--out", &out]);
    vref(&all, Duration::from_secs(60)).ok();
    out
}

/// The exact tier's product runs in AVX-512, AVX2 or baseline code by what
/// the CPU has; `VREF_SIMD` caps it, so every path this CPU has can be
/// checked end to end: all must give the same answers.
#[test]
fn every_simd_path_gives_the_exact_tier_the_same_answers() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = scenes_file(
        dir.path(),
        &[
            "--preset",
            "rigid",
            "--objects",
            "24",
            "--count",
            "3",
            "--seed",
            "5",
        ],
    );
    let scenes = scenes.as_str();
    let answers = |cap: &str| {
        let methods = ["paper", "rrwm", "sm"];
        json_lines(&answers_under_cap(
            dir.path(),
            scenes,
            &methods,
            "exact",
            cap,
        ))
    };
    let paths = simd_paths();
    let widest = answers(paths[0]);
    assert!(!widest.is_empty());
    for &cap in &paths[1..] {
        let narrower = answers(cap);
        assert_eq!(narrower.len(), widest.len(), "{cap}");
        for (a, b) in narrower.iter().zip(&widest) {
            // The same verdict for every object; confidences within
            // rounding (sums in another order).
            for key in ["scene", "method", "row", "correct", "matched"] {
                assert_eq!(a[key], b[key], "{cap}: {a} vs {b}");
            }
            let (ca, cb) = (
                a["confidence"].as_f64().unwrap(),
                b["confidence"].as_f64().unwrap(),
            );
            assert!((ca - cb).abs() <= 1e-6, "{cap}: {a} vs {b}");
        }
    }
}

/// `rigid`'s pair costs run in AVX2 or baseline code by what the CPU
/// has; each lane is the same IEEE arithmetic, so every path must give the
/// same answers and confidences to the bit. Scenes of the mrc preset are
/// ones no motion settles: the whole search runs.
#[test]
fn every_simd_path_gives_rigid_the_same_answers_to_the_bit() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = scenes_file(
        dir.path(),
        &["--preset", "mrc", "--count", "6", "--seed", "7"],
    );
    let scenes = scenes.as_str();
    let answers = |cap: &str| answers_under_cap(dir.path(), scenes, &["rigid"], "live", cap);
    let paths = simd_paths();
    let widest = answers(paths[0]);
    assert!(json_lines(&widest).len() > 20);
    for &cap in &paths[1..] {
        assert_eq!(answers(cap), widest, "{cap} against {}", paths[0]);
    }
}

/// The `VREF_SIMD` caps this CPU can run, widest first; those it lacks
/// are reported as skipped, so that no test compares a path with itself
/// under another name. Without AVX2 there is one path: the tests that
/// compare paths then check nothing but say so.
fn simd_paths() -> Vec<&'static str> {
    let mut paths = Vec::new();
    #[cfg(target_arch = "x86_64")]
    {
        let avx2 = std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma");
        if avx2 && std::arch::is_x86_feature_detected!("avx512f") {
            paths.push("avx512");
        } else {
            eprintln!("skipped: the AVX-512 path (this CPU has no AVX-512F)");
        }
        if avx2 {
            paths.push("avx2");
        } else {
            eprintln!("skipped: the AVX2 path (this CPU has no AVX2 and FMA)");
        }
    }
    paths.push("baseline");
    paths
}

#[test]
fn a_remote_query_to_nothing_says_where_it_tried_once_without_zenohs_noise() {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let endpoint = format!("tcp/127.0.0.1:{port}");
    let run = vref(
        &[
            "query",
            "--remote",
            &endpoint,
            "--prefix",
            "vref/nobody",
            "--latest-gesture",
        ],
        LIMIT,
    );
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(
        run.stderr
            .contains(&format!("connecting to {endpoint} over Zenoh")),
        "{}",
        run.stderr
    );
    // Zenoh's own warnings and source locations stay out of the message.
    assert!(!run.stderr.contains("WARN"), "{}", run.stderr);
    assert!(!run.stderr.contains(".rs:"), "{}", run.stderr);
}
