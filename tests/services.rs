//! The services as separate processes over real iceoryx2: matcher,
//! perception feed, gesture feed, and clients. Each test has its own
//! root path and prefix (vref_testkit::Harness).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::time::Duration;

use nix::sys::signal::Signal;
use support::table::table_harness;
use vref_inject::{robot_id, valid_objects};
use vref_scene::Side;
use vref_testkit::{Harness, eventually};
use vref_wire::ipc::ReferenceClient;
use vref_wire::{AnswerStatus, ObjectEntry, ReferenceAnswer};

fn human_objects() -> Vec<ObjectEntry> {
    valid_objects(Side::Human)
}

/// Where the robot sees the partner of human object `h`.
fn robot_position(h: u64) -> [f32; 3] {
    let robot = valid_objects(Side::Robot);
    robot
        .iter()
        .find(|o| o.track_id == robot_id(h))
        .map(|o| o.position)
        .unwrap()
}

fn start_feeds(h: &mut Harness, source: &str) {
    h.start(
        "perception",
        "vref-perception-feed",
        &["--source", source, "--rate", "50"],
    );
    h.start(
        "gesture",
        "vref-gesture-feed",
        &["--source", source, "--rate", "50"],
    );
}

fn start_all(h: &mut Harness, source: &str) {
    h.start("matcher", "vref-matcher", &[]);
    start_feeds(h, source);
}

/// Waits until the matcher answers `ok` for human object 1.
fn wait_ready(client: &mut ReferenceClient, h: &Harness) {
    eventually(Duration::from_secs(20), "first ok answer", || {
        let a = client.by_human_object(1, Duration::from_millis(300)).ok()?;
        (a.status() == AnswerStatus::Ok).then_some(())
    });
    let _ = h;
}

fn status_of(client: &mut ReferenceClient, id: u64) -> Option<AnswerStatus> {
    client
        .by_human_object(id, Duration::from_millis(300))
        .ok()
        .map(|a| a.status())
}

#[test]
fn a_pointed_object_is_answered_correctly_end_to_end() {
    let (mut h, ipc, source) = table_harness("e2e");
    start_all(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    wait_ready(&mut client, &h);
    for object in human_objects() {
        let human = object.track_id;
        let a = client
            .by_human_object(human, Duration::from_secs(2))
            .unwrap();
        assert_eq!(a.status(), AnswerStatus::Ok, "human {human}");
        assert_eq!(a.robot_track_id, robot_id(human), "human {human}");
        assert_eq!(a.position, robot_position(human));
        // Pointing from the headset at the object resolves to it too.
        let a = client
            .by_ray([0.0; 3], object.position, 0.05, Duration::from_secs(2))
            .unwrap();
        assert_eq!(
            (a.status(), a.human_object_id, a.robot_track_id),
            (AnswerStatus::Ok, human, robot_id(human))
        );
    }
    let unknown = client.by_human_object(99, Duration::from_secs(2)).unwrap();
    assert_eq!(unknown.status(), AnswerStatus::BadRequest);

    // The command line client reaches the same matcher.
    let run = support::vref(
        &[
            "query",
            "--human-object",
            "3",
            "--json",
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(20),
    )
    .ok();
    let answer: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert_eq!(answer["status"], "ok");
    assert_eq!(answer["robot_track_id"], robot_id(3));
}

#[test]
fn a_killed_feed_makes_answers_stale_and_a_restarted_feed_fresh() {
    let (mut h, ipc, source) = table_harness("stale");
    start_all(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    wait_ready(&mut client, &h);

    h.kill("perception");
    // stale_after_ms = 300 in the harness config.
    eventually(Duration::from_secs(5), "stale after the feed died", || {
        let a = client.by_human_object(2, Duration::from_millis(300)).ok()?;
        (a.status() == AnswerStatus::Stale).then_some(())
    });
    let a = client.by_human_object(2, Duration::from_secs(1)).unwrap();
    assert_eq!(a.robot_track_id, robot_id(2), "stale, not wrong");
    assert!(a.robot_age_us >= 300_000, "age {} us", a.robot_age_us);

    h.start(
        "perception",
        "vref-perception-feed",
        &["--source", &source, "--rate", "50"],
    );
    eventually(
        Duration::from_secs(15),
        "fresh after the feed restarted",
        || (status_of(&mut client, 2)? == AnswerStatus::Ok).then_some(()),
    );
}

/// `vref query --json` with exit code and the answer's JSON.
fn query_cli(h: &Harness, human: &str) -> (Option<i32>, serde_json::Value, String) {
    let run = support::vref(
        &[
            "query",
            "--human-object",
            human,
            "--timeout",
            "500ms",
            "--json",
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(20),
    );
    let json = serde_json::from_str(run.stdout.trim()).unwrap_or(serde_json::Value::Null);
    (run.code, json, run.stderr)
}

#[test]
fn vref_query_exit_codes_tell_not_ready_bad_request_and_stale_apart() {
    let (mut h, ipc, source) = table_harness("exits");
    h.start("matcher", "vref-matcher", &[]);
    // No feeds: once the matcher serves (1 while nobody does), not_ready.
    let (code, json, stderr) = eventually(Duration::from_secs(20), "a not_ready answer", || {
        let got = query_cli(&h, "1");
        (got.0 != Some(1)).then_some(got)
    });
    assert_eq!(code, Some(4), "{stderr}");
    assert_eq!(json["status"], "not_ready");
    assert_eq!(json["solved"], false);
    assert!(stderr.contains("not_ready"), "{stderr}");

    start_feeds(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    wait_ready(&mut client, &h);
    let (code, json, stderr) = query_cli(&h, "3");
    assert_eq!(code, Some(0), "{stderr}");
    assert_eq!(json["status"], "ok");
    assert!(json["solved"].is_boolean(), "{json}");
    let (code, json, stderr) = query_cli(&h, "99");
    assert_eq!(code, Some(3), "{stderr}");
    assert_eq!(json["status"], "bad_request");

    h.kill("perception");
    eventually(Duration::from_secs(5), "stale after the feed died", || {
        (status_of(&mut client, 2)? == AnswerStatus::Stale).then_some(())
    });
    let (code, json, stderr) = query_cli(&h, "2");
    assert_eq!(code, Some(5), "{stderr}");
    assert_eq!(json["status"], "stale");
}

#[test]
fn a_restarted_matcher_is_reached_again_by_the_same_client() {
    let (mut h, ipc, source) = table_harness("restart");
    start_all(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    wait_ready(&mut client, &h);

    h.kill("matcher");
    assert!(
        client
            .by_human_object(1, Duration::from_millis(300))
            .is_err(),
        "nobody should answer"
    );
    h.start("matcher", "vref-matcher", &[]);
    eventually(
        Duration::from_secs(20),
        "the same client reaches the new matcher",
        || {
            let a = client.by_human_object(4, Duration::from_millis(300)).ok()?;
            (a.status() == AnswerStatus::Ok && a.robot_track_id == robot_id(4)).then_some(())
        },
    );
}

#[test]
fn sigterm_stops_every_service_cleanly_and_nothing_blocks_the_next_start() {
    let (mut h, ipc, source) = table_harness("term");
    start_all(&mut h, &source);
    {
        let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
        wait_ready(&mut client, &h);
    }
    for name in ["gesture", "perception", "matcher"] {
        h.signal(name, Signal::SIGTERM);
        let status = h.wait(name, Duration::from_secs(10));
        assert_eq!(
            status.code(),
            Some(0),
            "{name} exit status:\n{}",
            h.log(name)
        );
    }
    start_all(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client-2").unwrap();
    wait_ready(&mut client, &h);
    for name in ["gesture", "perception", "matcher"] {
        h.signal(name, Signal::SIGINT);
        assert_eq!(
            h.wait(name, Duration::from_secs(10)).code(),
            Some(0),
            "{name}:\n{}",
            h.log(name)
        );
    }
}

#[test]
fn the_demo_answers_every_query_and_reports_its_accuracy() {
    let h = Harness::new("demo", "");
    let run = support::vref(
        &[
            "demo",
            "--duration",
            "4s",
            "--objects",
            "8",
            "--json",
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(120),
    )
    .ok();
    let summary: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    let queries = summary["queries"].as_u64().unwrap();
    assert!(queries >= 10, "{summary}");
    assert_eq!(summary["answered"], queries, "{summary}");
    assert_eq!(summary["errors"], 0, "{summary}");
    let correct = summary["correct"].as_u64().unwrap();
    let accuracy = summary["accuracy"].as_f64().unwrap();
    assert!(
        (accuracy - correct as f64 / queries as f64).abs() < 1e-9,
        "{summary}"
    );
    let wrong_pointing = summary["wrong_pointing"].as_u64().unwrap();
    let wrong_matching = summary["wrong_matching"].as_u64().unwrap();
    assert_eq!(
        wrong_pointing + wrong_matching,
        queries - correct,
        "every wrong answer has one cause: {summary}"
    );
    // The matcher is judged on its answers about the object pointed at.
    // Where the ray takes a neighbour (2 degrees of pointing error, drawn
    // once per 5 s gesture) it can do so for the whole gesture, so a 4 s
    // run can have most of its answers wrong with no fault of the
    // matcher: 11 of 750 answers of a 150 s demo, 6 of them in one
    // gesture. The end-to-end accuracy failed an earlier bound of 0.85 in
    // 3 of 14 runs of the eight service tests side by side. In 38 such
    // runs since (760 answers), every wrong answer but two had the ray
    // take a neighbour (the two: a lone `no_match` amid right answers), so
    // 3 wrong of 20 about the object meant is a matcher that errs.
    assert!(wrong_matching as f64 <= 0.15 * queries as f64, "{summary}");
}

/// `vref up` says where its services are, answers through them, and stops
/// them all in order on SIGTERM (exit 0, its run directory removed).
#[test]
fn vref_up_serves_clients_until_sigterm() {
    use std::io::{BufRead, BufReader};
    let mut up = std::process::Command::new(vref_testkit::binary("vref"))
        .args(["up", "--objects", "8"])
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Its lines, read on a thread so that every wait is bounded.
    let (lines, heard) = std::sync::mpsc::channel();
    let stdout = up.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if lines.send(line).is_err() {
                break;
            }
        }
    });
    let limit = Duration::from_secs(60);
    let first = heard.recv_timeout(limit).expect("vref up said nothing");
    let config = first
        .strip_prefix("config ")
        .unwrap_or_else(|| panic!("first line: {first}"))
        .to_owned();
    assert_eq!(heard.recv_timeout(limit).as_deref(), Ok("ready"));
    let run = support::vref(
        &["query", "--config", &config, "--latest-gesture", "--json"],
        Duration::from_secs(30),
    );
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let answer: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert!(answer["status"].is_string(), "{answer}");
    nix::sys::signal::kill(nix::unistd::Pid::from_raw(up.id() as i32), Signal::SIGTERM).unwrap();
    let status = vref_testkit::exit_within(&mut up, Duration::from_secs(30), || {
        "vref up after SIGTERM".to_owned()
    });
    vref_testkit::join_within(reader, Duration::from_secs(10), "vref up's output");
    assert_eq!(status.code(), Some(0));
    let run_dir = std::path::Path::new(&config).parent().unwrap();
    assert!(!run_dir.exists(), "{} was kept", run_dir.display());
}

/// Issue 40, case 1: both feeds replaced by a source whose features are
/// shorter (48 values to 6 in the report). Each side's first new snapshot
/// used to be refused against the other side's old one, for as long as
/// the matcher ran; now the second side's agreement lets both in. The
/// grace is set out of reach, so that only the agreement can.
#[test]
fn feeds_replaced_by_a_source_with_another_feature_length_are_answered() {
    let (mut h, ipc, source) =
        support::table::table_harness_with("fdim", "feature_dim_grace_ms = 600000\n", "");
    start_all(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    wait_ready(&mut client, &h);
    for feed in ["perception", "gesture"] {
        h.signal(feed, Signal::SIGINT);
        h.wait(feed, Duration::from_secs(10));
    }
    eventually(Duration::from_secs(10), "stale without feeds", || {
        (status_of(&mut client, 2)? == AnswerStatus::Stale).then_some(())
    });
    // The same table with the features cut to their first four values.
    let mut line: serde_json::Value =
        serde_json::from_str(support::table::dataset().trim()).unwrap();
    for side in ["robot", "human"] {
        for object in line[side]["objects"].as_array_mut().unwrap() {
            object["feature"].as_array_mut().unwrap().truncate(4);
        }
    }
    let shorter = h.dir.path().join("table-4.jsonl");
    std::fs::write(&shorter, format!("{line}\n")).unwrap();
    let shorter = format!("dataset:{}", shorter.display());
    // The robot's new feed alone: refused against the human side's old
    // snapshot, and the stale answers say so.
    h.start(
        "perception",
        "vref-perception-feed",
        &["--source", &shorter, "--rate", "50"],
    );
    let a = eventually(Duration::from_secs(10), "a stale answer naming why", || {
        let a = client.by_human_object(2, Duration::from_millis(300)).ok()?;
        (a.status() == AnswerStatus::Stale && a.flags & ReferenceAnswer::FLAG_REFUSAL != 0)
            .then_some(a)
    });
    assert_eq!(
        a.refusal,
        vref_reference::RejectReason::FeatureDimOtherSide as u32
    );
    h.start(
        "gesture",
        "vref-gesture-feed",
        &["--source", &shorter, "--rate", "50"],
    );
    let a = eventually(Duration::from_secs(15), "ok with 4 feature values", || {
        let a = client.by_human_object(2, Duration::from_millis(300)).ok()?;
        (a.status() == AnswerStatus::Ok).then_some(a)
    });
    assert_eq!(a.robot_track_id, robot_id(2));
    assert!(h.log("matcher").contains("feature_dim_other_side"));
}
