//! Load and process faults with the real services: a soak through `vref
//! soak`, and each service SIGKILLed and restarted while queries keep
//! coming. Each test has its own iceoryx2 root path and prefix.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use nix::sys::signal::Signal;
use support::table::table_harness;
use vref_inject::robot_id;
use vref_testkit::{Harness, eventually};
use vref_wire::AnswerStatus;
use vref_wire::ipc::{IpcError, IpcSettings, ReferenceClient, StatsReader};

#[test]
fn a_20_s_soak_at_100_hz_feeds_and_500_hz_queries_loses_nothing() {
    let run = support::vref(
        &[
            "soak",
            "--duration",
            "20s",
            "--feed-rate",
            "100",
            "--query-rate",
            "500",
            "--objects",
            "10",
            "--json",
        ],
        Duration::from_secs(120),
    )
    .ok();
    let s: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    let queries = s["queries"].as_u64().unwrap();
    // Not a rate check: only that the load really ran (500 Hz for 20 s
    // would be 10 000).
    assert!(queries >= 1000, "{s}");
    assert_eq!(s["timeouts"], 0, "{s}");
    assert_eq!(s["answered"], queries, "{s}");
    assert_eq!(s["unanswered"], 0, "{s}");
    assert_eq!(s["errors"]["ipc"], 0, "{s}");
    assert_eq!(s["errors"]["bad_request"], 0, "{s}");
    assert_eq!(s["errors"]["not_ready"], 0, "{s}");
    let rejected: u64 = s["rejected"]
        .as_object()
        .unwrap()
        .values()
        .map(|v| v.as_u64().unwrap())
        .sum();
    assert_eq!(rejected, 0, "{s}");
    for side in ["robot", "human"] {
        let published = s["snapshots"]["published"][side].as_u64().unwrap();
        let received = s["snapshots"]["received"][side].as_u64().unwrap();
        assert!(received > 0 && received <= published, "{side}: {s}");
        assert_eq!(s["snapshots"]["accepted"][side], received, "{side}: {s}");
    }
    let (start, end) = (
        s["rss_start_kb"].as_i64().unwrap(),
        s["rss_end_kb"].as_i64().unwrap(),
    );
    assert!(start > 0, "{s}");
    assert!(
        end - start < 2048,
        "resident memory grew by {} kB: {s}",
        end - start
    );
    // No query timed out, so none took longer than soak's 1 s query
    // timeout: a bound from outside the figures, where their order is
    // only the percentile's own.
    let max = s["rtt_max_us"].as_u64().unwrap();
    assert!(0 < max && max <= 1_000_000, "{s}");
}

#[test]
fn soak_help_names_its_flags_and_bad_rates_are_usage_errors() {
    let run = support::vref(&["soak", "--help"], Duration::from_secs(30)).ok();
    for flag in [
        "--duration",
        "--objects",
        "--feed-rate",
        "--query-rate",
        "--timeout",
        "--json",
        "warm-up",
    ] {
        assert!(run.stdout.contains(flag), "soak --help lacks {flag}");
    }
    for bad in [
        ["--query-rate", "0"],
        ["--feed-rate", "-5"],
        ["--timeout-ms", "0"],
        ["--timeout", "0s"],
        ["--duration", "soon"],
        ["--duration", "20"],
    ] {
        let args = ["soak", bad[0], bad[1]];
        let run = support::vref(&args, Duration::from_secs(30));
        assert_eq!(run.code, Some(2), "{args:?}: {}", run.stderr);
    }
}

/// What the background load saw in one phase of the fault test.
#[derive(Debug, Default, Clone)]
struct Counts {
    statuses: [u64; AnswerStatus::ALL.len()],
    timeouts: u64,
    failures: u64,
}

impl Counts {
    fn answered(&self) -> u64 {
        self.statuses.iter().sum()
    }

    fn of(&self, status: AnswerStatus) -> u64 {
        self.statuses[status as usize]
    }
}

/// Queries from their own client in a thread, about 200 a second, counted
/// by the phase they were sent in.
struct Load {
    phase: Arc<AtomicUsize>,
    /// The phase of the query the thread is asking (or about to).
    asking: Arc<AtomicUsize>,
    stop: Arc<AtomicBool>,
    oks: Arc<AtomicU64>,
    thread: Option<JoinHandle<Vec<Counts>>>,
}

const PHASES: usize = 5;

/// A query unanswered this long counts as lost. Not a latency bound: a
/// bound on what a feed's restart may cost a query, now that no intake or
/// solve runs on the query path.
const LOST_AFTER: Duration = Duration::from_millis(500);

impl Load {
    fn start(ipc: &IpcSettings) -> Self {
        let phase = Arc::new(AtomicUsize::new(0));
        let asking = Arc::new(AtomicUsize::new(0));
        let stop = Arc::new(AtomicBool::new(false));
        // A client is not Send: it is made in its thread.
        let ipc = ipc.clone();
        let oks = Arc::new(AtomicU64::new(0));
        let (p, a, s, o) = (phase.clone(), asking.clone(), stop.clone(), oks.clone());
        let thread = std::thread::spawn(move || {
            let mut client = ReferenceClient::connect(&ipc, "load-client").unwrap();
            let mut counts = vec![Counts::default(); PHASES];
            let mut id = 0;
            while !s.load(Ordering::SeqCst) {
                let at = p.load(Ordering::SeqCst);
                a.store(at, Ordering::SeqCst);
                id = id % 6 + 1;
                match client.by_human_object(id, LOST_AFTER) {
                    Ok(a) => {
                        if a.status() == AnswerStatus::Ok {
                            assert_eq!(a.robot_track_id, robot_id(id), "human {id}");
                            o.fetch_add(1, Ordering::SeqCst);
                        }
                        counts[at].statuses[a.status() as usize] += 1;
                    }
                    Err(IpcError::Timeout { .. } | IpcError::NoServer { .. }) => {
                        counts[at].timeouts += 1
                    }
                    Err(_) => counts[at].failures += 1,
                }
                std::thread::sleep(Duration::from_millis(5));
            }
            counts
        });
        Self {
            phase,
            asking,
            stop,
            oks,
            thread: Some(thread),
        }
    }

    /// Starts `phase` once the query in flight is answered: a query the
    /// previous phase sent is not in flight when this phase's fault
    /// begins, so that a matcher killed while answering it (phase 3)
    /// does not count its loss against the phase before.
    fn set_phase(&self, phase: usize) {
        self.phase.store(phase, Ordering::SeqCst);
        eventually(
            Duration::from_secs(20),
            &format!("the load asking in phase {phase}"),
            || (self.asking.load(Ordering::SeqCst) == phase).then_some(()),
        );
    }

    /// Waits until the load has had `n` more `ok` answers.
    fn wait_for_oks(&self, n: u64, what: &str) {
        let from = self.oks.load(Ordering::SeqCst);
        eventually(Duration::from_secs(20), what, || {
            (self.oks.load(Ordering::SeqCst) >= from + n).then_some(())
        });
    }

    fn finish(mut self) -> Vec<Counts> {
        self.stop.store(true, Ordering::SeqCst);
        self.thread.take().unwrap().join().unwrap()
    }
}

impl Drop for Load {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
    }
}

fn status(client: &mut ReferenceClient) -> Option<AnswerStatus> {
    client
        .by_human_object(2, Duration::from_millis(300))
        .ok()
        .map(|a| a.status())
}

fn wait_for(client: &mut ReferenceClient, wanted: AnswerStatus, what: &str) {
    eventually(Duration::from_secs(20), what, || {
        (status(client)? == wanted).then_some(())
    });
}

const FEED_ARGS: [&str; 2] = ["--rate", "100"];

fn start_feed(h: &mut Harness, name: &str, source: &str) {
    let bin = match name {
        "perception" => "vref-perception-feed",
        _ => "vref-gesture-feed",
    };
    let mut args = vec!["--source", source];
    args.extend(FEED_ARGS);
    h.start(name, bin, &args);
}

#[test]
fn each_service_killed_during_a_soak_and_restarted_leaves_the_matcher_answering() {
    let (mut h, ipc, source) = table_harness("kill");
    h.start("matcher", "vref-matcher", &[]);
    start_feed(&mut h, "perception", &source);
    start_feed(&mut h, "gesture", &source);
    let mut client = ReferenceClient::connect(&ipc, "test-client").unwrap();
    let stats = StatsReader::connect(&ipc, "test-stats").unwrap();
    wait_for(&mut client, AnswerStatus::Ok, "first ok answer");
    let load = Load::start(&ipc);
    load.wait_for_oks(20, "the load's first answers");

    // Phases 1 and 2: a feed dies; the matcher answers stale (from the
    // last snapshot), then fresh once the feed is back with a new session.
    for (phase, feed) in [(1, "perception"), (2, "gesture")] {
        load.set_phase(phase);
        h.kill(feed);
        wait_for(
            &mut client,
            AnswerStatus::Stale,
            &format!("stale without {feed}"),
        );
        // Let the load see the stale answers too.
        std::thread::sleep(Duration::from_millis(300));
        start_feed(&mut h, feed, &source);
        wait_for(
            &mut client,
            AnswerStatus::Ok,
            &format!("ok after {feed} restarted"),
        );
        load.wait_for_oks(5, &format!("the load's ok after {feed} restarted"));
    }
    let before = eventually(Duration::from_secs(5), "matcher statistics", || {
        stats.latest().unwrap()
    });
    assert_eq!(
        before.rejected_total(),
        0,
        "restarted feeds' snapshots must be taken, not refused: {before:?}"
    );
    assert!(
        before.snapshots_accepted.iter().all(|n| *n > 0),
        "{before:?}"
    );

    // Phase 3: the matcher dies and is started again without any cleanup;
    // the same clients reach it.
    load.set_phase(3);
    h.kill("matcher");
    assert!(status(&mut client).is_none(), "nobody should answer");
    h.start("matcher", "vref-matcher", &[]);
    wait_for(
        &mut client,
        AnswerStatus::Ok,
        "ok from the restarted matcher",
    );
    // The new matcher's statistics once they count an `ok` answer: its
    // first sample may be taken before it has answered anything.
    let after = eventually(
        Duration::from_secs(5),
        "the new matcher's statistics with an ok answer",
        || {
            stats
                .latest()
                .unwrap()
                .filter(|s| s.pid != before.pid && s.answered(AnswerStatus::Ok) > 0)
        },
    );
    assert!(after.started_ns > before.started_ns, "{after:?}");

    load.wait_for_oks(5, "the load's ok from the restarted matcher");

    // Phase 4: everything is back; nothing is lost any more.
    load.set_phase(4);
    std::thread::sleep(Duration::from_secs(2));
    let counts = load.finish();

    for (phase, c) in counts.iter().enumerate() {
        eprintln!("phase {phase}: {c:?}");
    }
    for phase in [0, 1, 2, 4] {
        let c = &counts[phase];
        assert_eq!((c.timeouts, c.failures), (0, 0), "phase {phase}: {c:?}");
        assert!(c.answered() > 0, "phase {phase}: {c:?}");
    }
    for phase in [1, 2] {
        let c = &counts[phase];
        assert!(c.of(AnswerStatus::Stale) > 0, "phase {phase}: {c:?}");
        assert!(c.of(AnswerStatus::Ok) > 0, "phase {phase}: {c:?}");
    }
    // The load's own client reached the restarted matcher too.
    assert!(counts[3].of(AnswerStatus::Ok) > 0, "{:?}", counts[3]);
    let c = &counts[4];
    assert_eq!(c.of(AnswerStatus::Ok), c.answered(), "phase 4: {c:?}");

    for name in ["gesture", "perception", "matcher"] {
        assert!(
            !h.log(name).contains("panicked"),
            "{name}:\n{}",
            h.log(name)
        );
        h.signal(name, Signal::SIGTERM);
        let code = h.wait(name, Duration::from_secs(10)).code();
        assert_eq!(code, Some(0), "{name}:\n{}", h.log(name));
    }
}

/// The commands that start the services say which one stopped at start and
/// why (the last line of its log), instead of waiting for answers that
/// cannot come, and keep its log.
#[test]
fn a_service_that_stops_at_start_is_named_with_its_reason() {
    let dir = tempfile::tempdir().unwrap();
    let vref = dir.path().join("vref");
    std::fs::copy(vref_testkit::binary("vref"), &vref).unwrap();
    for feed in ["vref-perception-feed", "vref-gesture-feed"] {
        std::fs::copy(vref_testkit::binary(feed), dir.path().join(feed)).unwrap();
    }
    // A matcher that refuses its configuration, as a matcher of another
    // version would.
    let matcher = dir.path().join("vref-matcher");
    std::fs::write(
        &matcher,
        "#!/bin/sh\necho 'ERROR configuration: unknown key matching.rigid.novelty' >&2\nexit 2\n",
    )
    .unwrap();
    std::fs::set_permissions(
        &matcher,
        std::os::unix::fs::PermissionsExt::from_mode(0o755),
    )
    .unwrap();
    for command in [
        &["demo", "--duration", "2s"][..],
        &["soak", "--duration", "2s"],
    ] {
        let run = support::vref_at(&vref, command, Duration::from_secs(60));
        assert_eq!(run.code, Some(1), "{command:?}: {}", run.stderr);
        assert!(
            run.stderr
                .contains("vref-matcher exited with exit status: 2: ERROR configuration: unknown key matching.rigid.novelty"),
            "{command:?}: {}",
            run.stderr
        );
        let kept = run
            .stderr
            .split("logs in ")
            .nth(1)
            .and_then(|rest| rest.split(')').next())
            .unwrap_or_else(|| panic!("{command:?} names no log directory: {}", run.stderr));
        let log = std::path::Path::new(kept).join("vref-matcher.log");
        assert!(log.exists(), "{command:?}: {} was not kept", log.display());
        std::fs::remove_dir_all(kept).ok();
    }
}
