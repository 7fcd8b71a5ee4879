//! Fault injection into the real matcher: `vref inject` writes one kind
//! of malformed message at a time, and the matcher must count and log the
//! defect, keep answering from the last good snapshots, take the next
//! valid one, and never panic. Each test has its own harness (root path
//! and prefix) and runs a group of kinds in turn.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::time::Duration;

use vref_harness::ready::{Readiness, wait_ready};
use vref_testkit::{Harness, eventually};
use vref_wire::ReferenceAnswer;
use vref_wire::ipc::ReferenceClient;
use vref_wire::{AnswerStatus, ipc::IpcSettings};

use vref_inject::robot_id;

/// One kind, where it goes, and what the matcher must say about it.
struct Fault {
    kind: &'static str,
    side: &'static str,
    /// `RejectReason::name` of the counter.
    reason: &'static str,
    /// A piece of the defect's description.
    defect: &'static str,
}

/// A matcher fed by `vref inject --kind valid` on both sides, and the
/// sequences of the snapshots it should be using.
struct Rig {
    // Dropped before the harness, which removes the iceoryx2 files.
    client: ReferenceClient,
    h: Harness,
    robot: u64,
    human: u64,
    /// `--count` of the next valid run, so each valid snapshot has its own
    /// sequence.
    next: u64,
}

fn inject(h: &Harness, kind: &str, side: &str, count: u64) {
    support::vref(
        &[
            "inject",
            "--kind",
            kind,
            "--side",
            side,
            "--count",
            &count.to_string(),
            "--config",
            h.config_arg(),
        ],
        Duration::from_secs(30),
    )
    .ok();
}

fn ask(client: &mut ReferenceClient) -> Option<ReferenceAnswer> {
    client.by_human_object(1, Duration::from_millis(500)).ok()
}

impl Rig {
    fn new(tag: &str) -> Self {
        let h = Harness::new(tag, "[matching]\nbeta = 0.01\n");
        // The valid snapshots come once per `inject` run, not at a rate:
        // with the harness's 300 ms the answers would turn `stale` and hide
        // whether the last good snapshot is still in force.
        let text = std::fs::read_to_string(&h.config).unwrap();
        assert!(text.contains("stale_after_ms = 300\n"), "{text}");
        std::fs::write(
            &h.config,
            text.replace("stale_after_ms = 300\n", "stale_after_ms = 600000\n"),
        )
        .unwrap();
        let ipc: IpcSettings = vref_config::Config::from_file(&h.config).unwrap().ipc;
        let mut rig = Rig {
            client: ReferenceClient::connect(&ipc, "fault-client").unwrap(),
            h,
            robot: 1,
            human: 1,
            next: 2,
        };
        rig.h.start("matcher", "vref-matcher", &[]);
        // Its subscribers exist once it answers at all (`not_ready`).
        eventually(Duration::from_secs(20), "matcher answers", || {
            ask(&mut rig.client)
        });
        inject(&rig.h, "valid", "robot", 1);
        inject(&rig.h, "valid", "human", 1);
        rig.expect_ok("both valid snapshots");
        rig
    }

    /// Waits for an `ok` answer from exactly the expected snapshots.
    fn expect_ok(&mut self, what: &str) {
        let (robot, human) = (self.robot, self.human);
        let answer = eventually(Duration::from_secs(15), what, || {
            let a = ask(&mut self.client)?;
            (a.status() == AnswerStatus::Ok
                && a.robot_sequence == robot
                && a.human_sequence == human)
                .then_some(a)
        });
        assert_eq!(answer.robot_track_id, robot_id(1), "{what}");
    }

    fn matcher_log(&self) -> String {
        self.h.log("matcher")
    }

    fn check(&mut self, fault: &Fault) {
        let Fault {
            kind,
            side,
            reason,
            defect,
        } = *fault;
        let tag = format!("reason={reason}");
        let logged = |log: &str| {
            log.lines()
                .filter(|l| l.contains(&tag) && l.contains(defect))
                .count()
        };
        let before = logged(&self.matcher_log());
        inject(&self.h, kind, side, 1);

        // (a) The defect is counted under its reason and described.
        let counted = wait_ready(Duration::from_secs(10), Duration::from_millis(50), || {
            Ok(if logged(&self.matcher_log()) > before {
                Readiness::Ready(())
            } else {
                Readiness::Waiting(format!("{kind}: `{tag}` line naming `{defect}`"))
            })
        });
        if let Err(e) = counted {
            panic!("{e}:\n{}", self.matcher_log());
        }
        // (b) The last good snapshots stay in force. `sequence-backwards`
        // sends a good sequence 10 before going back to 5.
        if kind == "sequence-backwards" {
            *self.side_sequence(side) = 10;
        }
        self.expect_ok(&format!("{kind}: still ok from the last good snapshots"));

        // (c) The next valid snapshot is used.
        let next = self.next;
        self.next += 1;
        let side = if kind == "zero-ray" { "robot" } else { side };
        inject(&self.h, "valid", side, next);
        *self.side_sequence(side) = next;
        self.expect_ok(&format!("{kind}: the next valid snapshot is used"));

        // (d) No panic, ever.
        let log = self.matcher_log();
        assert!(!log.contains("panicked"), "{kind}:\n{log}");
    }

    fn side_sequence(&mut self, side: &str) -> &mut u64 {
        match side {
            "robot" => &mut self.robot,
            "human" => &mut self.human,
            other => panic!("side {other}"),
        }
    }
}

fn run_all(tag: &str, faults: &[Fault]) {
    let mut rig = Rig::new(tag);
    for fault in faults {
        rig.check(fault);
    }
}

#[test]
fn malformed_positions_ids_and_up_vectors_are_refused_and_the_last_good_snapshot_stays() {
    run_all(
        "pos",
        &[
            Fault {
                kind: "nan",
                side: "robot",
                reason: "non_finite_position",
                defect: "is NaN, not a finite number",
            },
            Fault {
                kind: "inf",
                side: "human",
                reason: "non_finite_position",
                defect: "is inf, not a finite number",
            },
            Fault {
                kind: "huge",
                side: "robot",
                reason: "absurd_position",
                defect: "beyond the limit of",
            },
            Fault {
                kind: "duplicate-ids",
                side: "human",
                reason: "duplicate_id",
                defect: "appears more than once",
            },
            Fault {
                kind: "bad-up",
                side: "human",
                reason: "bad_up",
                defect: "up is [0.0, 0.0, 0.0], not a finite non-zero direction",
            },
        ],
    );
}

#[test]
fn malformed_headers_are_refused_and_the_last_good_snapshot_stays() {
    run_all(
        "hdr",
        &[
            Fault {
                kind: "count-over-slice",
                side: "robot",
                reason: "count_exceeds_slice",
                defect: "header says 11 objects, but the slice holds 6",
            },
            Fault {
                kind: "count-over-capacity",
                side: "human",
                reason: "too_many_objects",
                defect: "graph has 257 objects, more than the capacity of 256",
            },
            Fault {
                kind: "feature-dim-too-large",
                side: "robot",
                reason: "feature_dim_too_large",
                defect: "feature dimension 65 exceeds the wire maximum of 64",
            },
            Fault {
                kind: "schema-version",
                side: "human",
                reason: "schema_version",
                // The injected version is this build's plus 1000.
                defect: Box::leak(
                    format!(
                        "schema version {}, this build speaks {}",
                        vref_wire::SCHEMA_VERSION + 1000,
                        vref_wire::SCHEMA_VERSION
                    )
                    .into_boxed_str(),
                ),
            },
        ],
    );
}

#[test]
fn inconsistent_snapshots_and_bad_rays_are_refused_and_the_last_good_snapshot_stays() {
    run_all(
        "ctx",
        &[
            Fault {
                kind: "feature-dim-other-side",
                side: "human",
                reason: "feature_dim_other_side",
                defect: "feature dimension 4, the other side's is 6",
            },
            Fault {
                kind: "sequence-backwards",
                side: "robot",
                reason: "sequence_backwards",
                defect: "sequence 5 after 10 in the same session",
            },
            Fault {
                kind: "zero-ray",
                side: "robot",
                reason: "bad_ray",
                defect: "ray direction has zero length",
            },
        ],
    );
}

#[test]
fn stamps_from_the_future_or_an_hour_old_are_refused_and_the_last_good_snapshot_stays() {
    run_all(
        "stamp",
        &[
            Fault {
                kind: "future-stamp",
                side: "robot",
                reason: "timestamp_future",
                defect: "in the future, more than [matcher] max_clock_skew_ms = 100",
            },
            Fault {
                kind: "old-stamp",
                side: "human",
                reason: "timestamp_too_old",
                defect: "ms old, more than [matcher] max_capture_age_ms = 10000",
            },
        ],
    );
}

#[test]
fn an_unknown_kind_is_bad_input_and_lists_the_kinds() {
    let run = support::vref(&["inject", "--kind", "gremlins"], Duration::from_secs(20));
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    for kind in [
        "valid",
        "nan",
        "inf",
        "huge",
        "count-over-slice",
        "count-over-capacity",
        "feature-dim-too-large",
        "feature-dim-other-side",
        "duplicate-ids",
        "zero-ray",
        "schema-version",
        "sequence-backwards",
        "future-stamp",
        "old-stamp",
        "hijack-sequence",
        "hijack-ray",
        "bad-up",
    ] {
        assert!(run.stderr.contains(kind), "{kind} missing:\n{}", run.stderr);
    }
}
