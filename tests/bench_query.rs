//! `vref bench query` with real service processes: a short run reports
//! every documented figure, with all answers, cached answers, first
//! answers from a new solution, bare round trips and an idle matcher's
//! answers all measured, and no query lost. Timings themselves
//! are never asserted (they go in README).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::time::Duration;

use vref_testkit::Harness;

#[test]
fn a_short_run_reports_cached_solved_and_bare_round_trips() {
    // The harness's configuration only sets [matcher] timings here: the
    // command runs its services under a root path and prefix of its own.
    let h = Harness::new("bq", "");
    let run = support::vref(
        &[
            "bench",
            "query",
            "--objects",
            "8",
            "--rate",
            "100",
            "--duration",
            "2s",
            "--compare-idle",
            "--json",
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(120),
    )
    .ok();
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert_eq!(lines.len(), 1, "exactly one JSON object:\n{}", run.stdout);
    let report: serde_json::Value = serde_json::from_str(lines[0]).unwrap();
    assert_eq!(report["objects"], 8, "{report}");
    for key in [
        "all_p50_us",
        "all_p99_us",
        "ratio_all_p99",
        "all_p999_us",
        "idle_all_p50_us",
        "idle_all_p99_us",
        "ratio_busy_idle_p99",
        "solve_time_p50_us",
        "cached_p50_us",
        "cached_p99_us",
        "solve_p50_us",
        "solve_p99_us",
        "bare_p50_us",
        "bare_p99_us",
        "ratio_p99",
        "cached_p999_us",
        "solve_p999_us",
        "bare_p999_us",
    ] {
        let value = report[key].as_f64();
        assert!(value.is_some_and(|v| v > 0.0), "{key}: {report}");
    }
    // No query timed out (below), so no round trip took longer than the
    // benchmark's 2 s query timeout: a bound from outside the figures,
    // where their order is only the percentile's own.
    for kind in ["all", "cached", "solve", "bare"] {
        let count = report[format!("{kind}_count")].as_u64().unwrap();
        assert!(count > 0, "no {kind} round trips: {report}");
        let p999 = report[format!("{kind}_p999_us")].as_f64().unwrap();
        assert!(p999 <= 2e6, "{kind}: {report}");
    }
    // The idle phase's feeds publish where the matcher does not hear
    // them: it solves nothing then, and everything once they are heard.
    assert_eq!(report["idle_solve_time_count"], 0, "{report}");
    assert!(report["solve_time_count"].as_u64().unwrap() > 0, "{report}");
    assert_eq!(report["timeouts"], 0, "{report}");
    assert_eq!(report["errors"], 0, "{report}");
    // Two matcher queries and one bare query per tick.
    let matcher = report["cached_count"].as_u64().unwrap()
        + report["solve_count"].as_u64().unwrap()
        + report["other_count"].as_u64().unwrap();
    assert_eq!(
        matcher,
        2 * report["bare_count"].as_u64().unwrap(),
        "{report}"
    );
    assert_eq!(report["all_count"].as_u64().unwrap(), matcher, "{report}");
}

#[test]
fn too_few_objects_or_a_bad_rate_are_bad_input() {
    for args in [
        &["bench", "query", "--objects", "1"][..],
        &["bench", "query", "--rate", "0"][..],
        &["bench", "query", "--duration", "soon"][..],
    ] {
        let run = support::vref(args, Duration::from_secs(30));
        assert_eq!(run.code, Some(2), "{args:?}: {}", run.stderr);
    }
}

#[test]
fn the_client_bench_measures_a_running_matcher() {
    let mut h = Harness::new("bc", "");
    h.start("matcher", "vref-matcher", &[]);
    h.start("perception", "vref-perception-feed", &["--objects", "8"]);
    h.start("gesture", "vref-gesture-feed", &["--objects", "8"]);
    let run = support::vref(
        &[
            "bench",
            "client",
            "--rate",
            "100",
            "--duration",
            "2s",
            "--json",
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(120),
    )
    .ok();
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert_eq!(lines.len(), 1, "exactly one JSON object:\n{}", run.stdout);
    let report: serde_json::Value = serde_json::from_str(lines[0]).unwrap();
    assert_eq!(report["client"], "rust", "{report}");
    let cached = report["cached_count"].as_u64().unwrap();
    assert!(cached > 0, "no cached answers: {report}");
    // Within the client benchmark's 2 s query timeout (none timed out).
    let p99 = report["cached_p99_us"].as_f64().unwrap();
    assert!(0.0 < p99 && p99 <= 2e6, "{report}");
    assert_eq!(
        (&report["timeouts"], &report["errors"]),
        (&0.into(), &0.into()),
        "{report}"
    );
}

#[test]
fn the_client_bench_without_a_matcher_fails_and_says_so() {
    let h = Harness::new("bcn", "");
    let run = support::vref(
        &[
            "bench",
            "client",
            "--duration",
            "1s",
            "--ready-within",
            "1s",
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(60),
    );
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(run.stderr.contains("no ok or ambiguous"), "{}", run.stderr);
}
