//! What a hostile or unlucky user can do to the running services, each
//! tried against real processes (docs/reliability.md): one message with
//! the largest sequence, an old ray, one controller too many, a matcher
//! restarted under a waiting query, a client flooding requests, and a
//! solve that takes seconds. Each test has its own root path and prefix.
//! Also the suite's own guard: a test that hangs is aborted, named.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use nix::sys::signal::Signal;
use support::table::table_harness_with;
use vref_inject::{HIJACK_RAY_TARGET, robot_id, valid_objects};
use vref_scene::Side;
use vref_testkit::{Harness, eventually, join_within};
use vref_wire::ipc::{
    DecisionReader, GesturePublisher, IpcError, IpcSettings, ReferenceClient, StatsReader,
    create_node, open_reference, open_request_event,
};
use vref_wire::{AnswerStatus, MatcherStats, ReferenceAnswer, ReferenceQuery};

/// The counter of a reject reason in `MatcherStats::rejected`.
fn rejected(stats: &MatcherStats, reason: &str) -> u64 {
    let index = vref_reference::RejectReason::ALL
        .iter()
        .position(|r| r.name() == reason)
        .unwrap();
    stats.rejected[index]
}

fn start_all(h: &mut Harness, source: &str) {
    h.start("matcher", "vref-matcher", &[]);
    for (name, bin) in [
        ("perception", "vref-perception-feed"),
        ("gesture", "vref-gesture-feed"),
    ] {
        h.start(name, bin, &["--source", source, "--rate", "50"]);
    }
}

fn ask(client: &mut ReferenceClient, id: u64) -> Option<ReferenceAnswer> {
    client.by_human_object(id, Duration::from_millis(500)).ok()
}

fn wait_ok(client: &mut ReferenceClient) {
    eventually(Duration::from_secs(20), "first ok answer", || {
        (ask(client, 1)?.status() == AnswerStatus::Ok).then_some(())
    });
}

fn inject(h: &Harness, kind: &str, side: &str) {
    support::vref(
        &[
            "inject",
            "--kind",
            kind,
            "--side",
            side,
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(30),
    )
    .ok();
}

/// A gesture feed of the test's own: from the headset's origin toward
/// human object `id`, every 20 ms until dropped.
struct Pointing {
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Pointing {
    fn at(ipc: &IpcSettings, id: u64) -> Self {
        let target = valid_objects(Side::Human)
            .into_iter()
            .find(|o| o.track_id == id)
            .unwrap()
            .position;
        let stop = Arc::new(AtomicBool::new(false));
        let (ipc, halt) = (ipc.clone(), stop.clone());
        // Ports are not Send: made in the thread.
        let thread = std::thread::spawn(move || {
            let node = create_node(&ipc, "test-pointing").unwrap();
            let mut rays = GesturePublisher::new(&node, &ipc).unwrap();
            while !halt.load(Ordering::SeqCst) {
                rays.publish([0.0; 3], target, 0.05, 0.9).unwrap();
                std::thread::sleep(Duration::from_millis(20));
            }
        });
        Self {
            stop,
            thread: Some(thread),
        }
    }
}

impl Drop for Pointing {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(t) = self.thread.take() {
            t.join().ok();
        }
    }
}

fn latest_gesture(client: &mut ReferenceClient) -> Option<ReferenceAnswer> {
    client.latest_gesture(Duration::from_millis(500)).ok()
}

#[test]
fn one_message_with_the_largest_sequence_locks_out_no_feed() {
    let (mut h, ipc, source) = table_harness_with("hijack", "", "");
    start_all(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    let stats = StatsReader::connect(&ipc, "test-stats").unwrap();
    wait_ok(&mut client);
    let pointing = Pointing::at(&ipc, 1);
    eventually(Duration::from_secs(10), "the test's rays", || {
        let a = latest_gesture(&mut client)?;
        (a.status() == AnswerStatus::Ok && a.human_object_id == 1).then_some(())
    });
    assert_ne!(HIJACK_RAY_TARGET, 1);

    // The feeds' own sessions, read as any subscriber can, with sequence
    // 2^64 - 1: snapshots on both sides and a ray.
    let before = ask(&mut client, 1).unwrap();
    inject(&h, "hijack-sequence", "robot");
    inject(&h, "hijack-sequence", "human");
    inject(&h, "hijack-ray", "robot");

    // The feeds' next messages are still taken.
    let after = eventually(
        Duration::from_secs(10),
        "the feeds' snapshots after",
        || {
            let a = ask(&mut client, 1)?;
            (a.status() == AnswerStatus::Ok
                && a.robot_sequence > before.robot_sequence + 25
                && a.robot_sequence < u64::MAX
                && a.human_sequence > before.human_sequence + 25
                && a.human_sequence < u64::MAX)
                .then_some(a)
        },
    );
    assert_eq!(after.robot_track_id, robot_id(1));
    eventually(Duration::from_secs(10), "the test's rays after", || {
        let a = latest_gesture(&mut client)?;
        (a.status() == AnswerStatus::Ok && a.human_object_id == 1 && a.ray_age_us < 200_000)
            .then_some(())
    });
    drop(pointing);
    let s = eventually(Duration::from_secs(5), "statistics", || {
        stats.latest().unwrap()
    });
    for reason in ["sequence_backwards", "sequence_jump"] {
        assert_eq!(rejected(&s, reason), 0, "{reason}: {s:?}");
    }
    let log = h.log("matcher");
    assert!(!log.contains("panicked"), "{log}");
}

#[test]
fn a_ray_older_than_ray_max_age_makes_latest_gesture_answers_stale() {
    let (mut h, ipc, source) = table_harness_with("oldray", "ray_max_age_ms = 400\n", "");
    start_all(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    wait_ok(&mut client);
    let node = create_node(&ipc, "test-one-ray").unwrap();
    let mut rays = GesturePublisher::new(&node, &ipc).unwrap();
    let target = valid_objects(Side::Human)[1];
    let answered = eventually(Duration::from_secs(10), "the ray's answer", || {
        // One ray, published until the matcher has it.
        let a = latest_gesture(&mut client)?;
        if a.status() != AnswerStatus::Ok {
            rays.publish([0.0; 3], target.position, 0.05, 0.9).unwrap();
            return None;
        }
        Some(a)
    });
    assert_eq!(answered.human_object_id, target.track_id);
    let stale = eventually(Duration::from_secs(10), "stale past 400 ms", || {
        let a = latest_gesture(&mut client)?;
        (a.status() == AnswerStatus::Stale).then_some(a)
    });
    assert!(stale.ray_age_us >= 400_000, "{stale:?}");
    assert_eq!(
        stale.robot_track_id,
        robot_id(target.track_id),
        "stale, not wrong"
    );
    // The snapshots are fresh: only the ray is old.
    assert_eq!(ask(&mut client, 1).unwrap().status(), AnswerStatus::Ok);
}

#[test]
fn exactly_max_clients_controllers_connect_and_the_next_is_told_the_limit() {
    // 22 is above iceoryx2's default node limit of a service (20).
    for limit in [3usize, 22] {
        let tag = format!("lim{limit}");
        let (mut h, ipc, _) = table_harness_with(&tag, "", &format!("max_clients = {limit}\n"));
        h.start("matcher", "vref-matcher", &[]);
        let mut clients: Vec<ReferenceClient> = (0..limit)
            .map(|k| ReferenceClient::connect(&ipc, &format!("controller-{k}")).unwrap())
            .collect();
        for client in &mut clients {
            // No feeds: `not_ready`, but answered.
            eventually(Duration::from_secs(20), "an answer", || ask(client, 1));
        }
        let refused = ReferenceClient::connect(&ipc, "one-too-many").unwrap_err();
        assert_eq!(refused, IpcError::TooManyClients { limit }, "{refused}");
        assert!(
            refused
                .to_string()
                .contains(&format!("[ipc] max_clients = {limit}")),
            "{refused}"
        );
        let run = support::vref(
            &["query", "--human-object", "1", "--config", h.config_arg()],
            Duration::from_secs(20),
        );
        assert_eq!(run.code, Some(1), "{}", run.stderr);
        assert!(run.stderr.contains("max_clients"), "{}", run.stderr);
        // A place freed is a place taken.
        clients.pop();
        ReferenceClient::connect(&ipc, "the-next").unwrap();
    }
}

#[test]
fn a_query_waiting_through_a_matcher_restart_is_answered_by_the_new_one() {
    let (mut h, ipc, source) = table_harness_with("wait", "", "");
    start_all(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    wait_ok(&mut client);
    let waiting = |ipc: &IpcSettings, id: u64| {
        let ipc = ipc.clone();
        std::thread::spawn(move || {
            let mut client = ReferenceClient::connect(&ipc, &format!("waiting-{id}")).unwrap();
            client.by_human_object(id, Duration::from_secs(30))
        })
    };

    // A stalled matcher: `vref query` says it is there but did not answer.
    h.signal("matcher", Signal::SIGSTOP);
    let run = support::vref(
        &[
            "query",
            "--human-object",
            "1",
            "--timeout",
            "300ms",
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(20),
    );
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(run.stderr.contains("busy or stalled"), "{}", run.stderr);
    assert!(
        !run.stderr.contains("is vref-matcher running"),
        "{}",
        run.stderr
    );

    // A query waiting when the stalled matcher is killed.
    let asked = waiting(&ipc, 3);
    std::thread::sleep(Duration::from_millis(300));
    h.kill("matcher");
    h.start("matcher", "vref-matcher", &[]);
    let answer = join_within(asked, Duration::from_secs(40), "the waiting query").unwrap();
    assert!(
        matches!(answer.status(), AnswerStatus::Ok | AnswerStatus::NotReady),
        "{answer:?}"
    );

    // A query sent while no matcher runs; and `vref query` then says so
    // (asked with the former spelling, --timeout-ms, which still works).
    h.kill("matcher");
    let run = support::vref(
        &[
            "query",
            "--human-object",
            "1",
            "--timeout-ms",
            "300",
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(20),
    );
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(
        run.stderr.contains("is vref-matcher running"),
        "{}",
        run.stderr
    );
    let asked = waiting(&ipc, 4);
    std::thread::sleep(Duration::from_millis(500));
    h.start("matcher", "vref-matcher", &[]);
    let answer = join_within(asked, Duration::from_secs(40), "the waiting query").unwrap();
    assert!(
        matches!(answer.status(), AnswerStatus::Ok | AnswerStatus::NotReady),
        "{answer:?}"
    );
    wait_ok(&mut client);
}

/// SIGSTOP then SIGCONT (a debugger, `kill -STOP`, a suspended terminal)
/// cut the services' waits short without asking them to stop: they go
/// on answering from new snapshots, and SIGTERM still stops them.
#[test]
fn stopped_and_continued_services_keep_running() {
    let (mut h, ipc, source) = table_harness_with("cont", "", "");
    start_all(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    wait_ok(&mut client);
    let before = ask(&mut client, 1).unwrap().robot_sequence;
    let names = ["matcher", "perception", "gesture"];
    for _ in 0..3 {
        for name in names {
            h.signal(name, Signal::SIGSTOP);
        }
        std::thread::sleep(Duration::from_millis(200));
        for name in names {
            h.signal(name, Signal::SIGCONT);
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    std::thread::sleep(Duration::from_millis(500));
    for name in names {
        assert!(h.running(name), "{name} exited:\n{}", h.log(name));
    }
    eventually(
        Duration::from_secs(10),
        "an ok answer from a newer snapshot",
        || {
            let answer = ask(&mut client, 1)?;
            (answer.status() == AnswerStatus::Ok && answer.robot_sequence > before).then_some(())
        },
    );
    for name in names {
        h.signal(name, Signal::SIGTERM);
        let status = h.wait(name, Duration::from_secs(10));
        assert_eq!(status.code(), Some(0), "{name}:\n{}", h.log(name));
    }
}

/// Sends requests as fast as it can and never reads an answer.
fn flood(ipc: &IpcSettings, stop: &AtomicBool, sent: &AtomicU64) {
    let node = create_node(ipc, "test-flooder").unwrap();
    let client = open_reference(&node, ipc)
        .unwrap()
        .client_builder()
        .create()
        .unwrap();
    let notifier = open_request_event(&node, ipc)
        .unwrap()
        .notifier_builder()
        .create()
        .unwrap();
    let query = ReferenceQuery {
        request_id: 1,
        ..ReferenceQuery::human_object(1)
    };
    while !stop.load(Ordering::SeqCst) {
        if let Ok(request) = client.loan_uninit() {
            // Dropped at once: its answer is never read.
            if request.write_payload(query).send().is_ok() {
                sent.fetch_add(1, Ordering::Relaxed);
            }
        }
        notifier.notify().ok();
    }
}

#[test]
fn a_flooding_client_gets_its_rate_and_a_well_behaved_client_all_its_answers() {
    let (mut h, ipc, source) =
        table_harness_with("flood", "max_queries_per_client_hz = 100.0\n", "");
    start_all(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    let stats = StatsReader::connect(&ipc, "test-stats").unwrap();
    wait_ok(&mut client);
    let stop = Arc::new(AtomicBool::new(false));
    let sent = Arc::new(AtomicU64::new(0));
    let flooder = {
        let (ipc, stop, sent) = (ipc.clone(), stop.clone(), sent.clone());
        std::thread::spawn(move || flood(&ipc, &stop, &sent))
    };
    // The well-behaved client asks below the rate, one query at a time.
    let mut lost = 0;
    for k in 0..100u64 {
        let id = k % 6 + 1;
        match client.by_human_object(id, Duration::from_millis(500)) {
            Ok(a) => {
                assert_eq!(a.status(), AnswerStatus::Ok, "{a:?}");
                assert_eq!(a.robot_track_id, robot_id(id));
            }
            Err(e) => {
                eprintln!("query {k}: {e}");
                lost += 1;
            }
        }
        std::thread::sleep(Duration::from_millis(15));
    }
    stop.store(true, Ordering::SeqCst);
    flooder.join().unwrap();
    assert_eq!(lost, 0, "the well-behaved client lost queries");
    let s = eventually(Duration::from_secs(5), "statistics after the flood", || {
        stats
            .latest()
            .unwrap()
            .filter(|s| rejected(s, "query_over_rate") > 0)
    });
    let flooded = sent.load(Ordering::SeqCst);
    eprintln!(
        "flooder sent {flooded}, answered {} in all, dropped {}",
        s.answered_total(),
        rejected(&s, "query_over_rate")
    );
    assert!(s.answered_total() < flooded, "{s:?}");
    // One line for the flooder's dropped queries, then counts.
    let log = h.log("matcher");
    let lines = log
        .lines()
        .filter(|l| l.contains("query_over_rate"))
        .count();
    assert!(lines <= 3, "{lines} lines:\n{log}");
}

/// Stats samples and decisions seen while one long solve ran.
#[test]
fn snapshots_statistics_and_answers_keep_flowing_during_a_long_solve() {
    // The exact tier at 128 objects solves for seconds: accepted only with
    // a freshness budget that long.
    let h_extra = "method = \"paper\"\ntier = \"exact\"\nstale_after_ms = 120000\n";
    let mut h = Harness::new("long", &format!("{h_extra}[scene]\ncapacity = 128\n"));
    let text = std::fs::read_to_string(&h.config).unwrap();
    std::fs::write(&h.config, text.replace("stale_after_ms = 300\n", "")).unwrap();
    let ipc = vref_config::Config::from_file(&h.config).unwrap().ipc;
    let scenes = h.dir.path().join("big.jsonl");
    support::vref(
        &[
            "scenes",
            "--preset",
            "rigid",
            "--objects",
            "128",
            "--count",
            "2",
            "--seed",
            "1",
            "--out",
            scenes.to_str().unwrap(),
        ],
        Duration::from_secs(60),
    )
    .ok();
    let source = format!("dataset:{}", scenes.display());
    h.start("matcher", "vref-matcher", &[]);
    // The two scenes alternate, so every solve has new positions to solve.
    for (name, bin) in [
        ("perception", "vref-perception-feed"),
        ("gesture", "vref-gesture-feed"),
    ] {
        h.start(
            name,
            bin,
            &["--source", &source, "--rate", "30", "--hold", "200ms"],
        );
    }
    let stats = StatsReader::connect(&ipc, "test-stats").unwrap();
    let decisions = DecisionReader::connect(&ipc, "test-decisions").unwrap();
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    let mut samples: Vec<MatcherStats> = Vec::new();
    let mut answered_ns: Vec<u64> = Vec::new();
    // The first solve alone takes seconds, and on a loaded machine a
    // minute or more (90 s was too short with both cores busy elsewhere).
    let found = eventually(
        Duration::from_secs(180),
        "a long solve with intake beside it",
        || {
            if let Some(s) = stats.latest().unwrap() {
                samples.push(s);
            }
            if client
                .by_human_object(0, Duration::from_millis(200))
                .is_ok()
            {
                answered_ns.push(vref_wire::ipc::now_ns());
            }
            let decision = decisions.latest().unwrap()?.unwrap();
            let h = decision.header;
            let (from, to) = (h.solved_ns - h.solve_us * 1000, h.solved_ns);
            let during: Vec<&MatcherStats> = samples
                .iter()
                .filter(|s| s.taken_ns > from && s.taken_ns < to)
                .collect();
            let accepted = |s: &MatcherStats| s.snapshots_accepted.iter().sum::<u64>();
            let intake = during.windows(2).any(|w| accepted(w[1]) > accepted(w[0]));
            let answers = answered_ns.iter().any(|&t| t > from && t < to);
            (h.solve_us >= 500_000 && intake && answers).then_some((h, during.len()))
        },
    );
    eprintln!(
        "solve {} took {} ms; {} statistics samples during it",
        found.0.solve_index,
        found.0.solve_us / 1000,
        found.1
    );
    assert!(!h.log("matcher").contains("panicked"));
}

/// Nodes under `ipc`'s root path that are dead (their process is gone).
fn dead_nodes(ipc: &IpcSettings) -> usize {
    use iceoryx2::prelude::*;
    let node = create_node(ipc, "dead-node-counter").unwrap();
    let mut dead = 0;
    Node::<ipc::Service>::list(node.config(), |state| {
        if matches!(state, NodeState::Dead(_)) {
            dead += 1;
        }
        CallbackProgression::Continue
    })
    .unwrap();
    dead
}

#[test]
fn the_matcher_cleans_up_after_a_killed_feed_on_its_own() {
    let (mut h, ipc, source) = table_harness_with("dead", "", "");
    start_all(&mut h, &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    wait_ok(&mut client);
    // The test only looks: nobody but the matcher cleans up here.
    h.kill("gesture");
    eventually(
        Duration::from_secs(10),
        "the matcher cleaning up the dead feed's node",
        || (h.log("matcher").contains("dead nodes") && dead_nodes(&ipc) == 0).then_some(()),
    );
    // The query path went on meanwhile.
    assert!(ask(&mut client, 1).is_some());
}

/// Not a test of vref: a test that hangs, for the one below to run in a
/// child process with a short limit.
#[test]
#[ignore = "hangs on purpose; run by a_hung_test_is_aborted_naming_it_and_its_services_killed"]
fn hangs_on_purpose() {
    let mut h = Harness::new("hang", "");
    h.start("matcher", "vref-matcher", &[]);
    std::thread::sleep(Duration::from_secs(120));
}

#[test]
fn a_hung_test_is_aborted_naming_it_and_its_services_killed() {
    // The suite's guard against a call that never returns (vref_testkit::test_limit).
    let this = std::env::current_exe().unwrap();
    let run = support::vref_with(
        &this,
        &["--ignored", "--exact", "hangs_on_purpose"],
        &[("VREF_TEST_LIMIT_SECS", "2")],
        Duration::from_secs(100),
    );
    assert_ne!(run.code, Some(0), "{}", run.stderr);
    let report = &run.stderr;
    assert!(
        report.contains("hangs_on_purpose: still running after 2s"),
        "{report}"
    );
    assert!(report.contains("matcher.log"), "{report}");
    let pid: i32 = report
        .split("killed matcher (pid ")
        .nth(1)
        .and_then(|rest| rest.split(')').next())
        .and_then(|pid| pid.parse().ok())
        .unwrap_or_else(|| panic!("no killed matcher in:\n{report}"));
    // Gone, or a zombie where nobody reaps the orphan (PID 1 in a container).
    let gone = || match std::fs::read_to_string(format!("/proc/{pid}/stat")) {
        Err(_) => true,
        Ok(stat) => stat
            .rsplit(')')
            .next()
            .is_some_and(|rest| rest.trim_start().starts_with('Z')),
    };
    eventually(
        Duration::from_secs(10),
        "the hung test's matcher gone",
        || gone().then_some(()),
    );
    if report.contains("--- backtraces") {
        assert!(report.contains("hangs_on_purpose"), "{report}");
    }
}
