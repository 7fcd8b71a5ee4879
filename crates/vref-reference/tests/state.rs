#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::sync::Arc;
use std::time::Duration;

use vref_match::Params;
use vref_reference::{
    MatcherSettings, Now, Origin, ReferenceState, RejectReason, Solved, Solver, decision_entry,
    decision_header, decision_len,
};
use vref_scene::{Limits, Side};
use vref_wire::{
    AnswerStatus, DecisionEntry, DecisionHeader, FRAME_NAME_LEN, MAX_FEATURE_DIM, ObjectEntry,
    PointingRay, QueryKind, ReferenceAnswer, ReferenceQuery, SCHEMA_VERSION, SideCode,
    SnapshotHeader,
};

/// Four objects on a table: distinct shapes of the layout, features that
/// tell them apart.
const WORLD: [[f32; 3]; 4] = [
    [0.0, 0.0, 1.0],
    [0.3, 0.0, 1.2],
    [-0.2, 0.1, 1.5],
    [0.1, 0.2, 0.9],
];

fn entries(ids: &[u64], shift: f32) -> Vec<ObjectEntry> {
    WORLD
        .iter()
        .zip(ids)
        .enumerate()
        .map(|(k, (p, &id))| {
            let mut feature = [0.0; MAX_FEATURE_DIM];
            feature[k] = 1.0;
            ObjectEntry {
                track_id: id,
                position: [p[0] + shift, p[1], p[2]],
                position_sigma: [0.0; 3],
                feature,
            }
        })
        .collect()
}

fn header(side: Side, session: u64, sequence: u64, count: usize, now: &Now) -> SnapshotHeader {
    SnapshotHeader {
        session,
        sequence,
        timestamp_ns: now.unix_ns,
        schema_version: SCHEMA_VERSION,
        side: if side == Side::Robot {
            SideCode::Robot as u32
        } else {
            SideCode::Human as u32
        },
        object_count: count as u32,
        feature_dim: 4,
        frame_name: [0; FRAME_NAME_LEN],
        up: [0.0; 3],
        flags: 0,
    }
}

const HUMAN_IDS: [u64; 4] = [1, 2, 3, 4];
const ROBOT_IDS: [u64; 4] = [40, 30, 20, 10];
/// Publisher ports of the two feeds and of the gesture feed.
const ROBOT_FEED: Origin = 100;
const HUMAN_FEED: Origin = 200;
const GESTURES: Origin = 300;

fn settings(method: &str) -> MatcherSettings {
    MatcherSettings {
        method: method.to_owned(),
        ..MatcherSettings::default()
    }
}

/// The intake and the solver, driven by hand in the order the service's
/// two threads would run them.
struct Rig {
    state: ReferenceState,
    solver: Solver,
}

impl Rig {
    fn new(settings: &MatcherSettings) -> Self {
        Self {
            state: ReferenceState::new(settings, Limits::default()).unwrap(),
            solver: Solver::new(settings, Params::default()).unwrap(),
        }
    }

    /// Solves the newest pair and makes it the one queries read.
    fn solve(&mut self) -> Arc<Solved> {
        let pair = self.state.latest_pair().unwrap();
        let solved = Arc::new(self.solver.solve(&pair).unwrap());
        self.state.install(solved.clone());
        solved
    }

    fn answer(&self, q: &ReferenceQuery, now: &Now) -> ReferenceAnswer {
        self.state.answer(q, now)
    }
}

fn state(method: &str) -> Rig {
    Rig::new(&settings(method))
}

/// Both views of the four objects, snapshot `sequence` of each feed; the
/// robot sees the table shifted by 0.5 m.
fn publish_both(s: &mut Rig, sequence: u64, now: &Now) {
    publish_moved(s, sequence, 0.0, now);
}

/// ... with the human view's objects moved by `shift` along x.
fn publish_moved(s: &mut Rig, sequence: u64, shift: f32, now: &Now) {
    s.state
        .accept_snapshot(
            Side::Robot,
            ROBOT_FEED,
            &header(Side::Robot, 1, sequence, 4, now),
            &entries(&ROBOT_IDS, 0.5 + shift),
            now,
        )
        .unwrap();
    s.state
        .accept_snapshot(
            Side::Human,
            HUMAN_FEED,
            &header(Side::Human, 2, sequence, 4, now),
            &entries(&HUMAN_IDS, shift),
            now,
        )
        .unwrap();
}

fn ready_with(settings: MatcherSettings, now: &Now) -> Rig {
    let mut s = Rig::new(&settings);
    publish_both(&mut s, 1, now);
    s.solve();
    s
}

fn ready(now: &Now) -> Rig {
    ready_with(settings("paper"), now)
}

fn query(kind: QueryKind, id: u64, origin: [f32; 3], direction: [f32; 3]) -> ReferenceQuery {
    ReferenceQuery {
        request_id: 9,
        human_object_id: id,
        ray_origin: origin,
        ray_direction: direction,
        cone_half_angle: 0.1,
        kind: kind as u32,
        schema_version: SCHEMA_VERSION,
        reserved: 0,
    }
}

fn by_id(id: u64) -> ReferenceQuery {
    query(QueryKind::HumanObject, id, [0.0; 3], [0.0; 3])
}

/// The person's first gesture, from the origin toward object 4 of the
/// human view, captured at `now`.
fn pointing_at_object_4(now: &Now) -> PointingRay {
    PointingRay {
        session: 5,
        sequence: 1,
        timestamp_ns: now.unix_ns,
        origin: [0.0; 3],
        direction: WORLD[3],
        cone_half_angle: 0.05,
        confidence: 1.0,
        schema_version: SCHEMA_VERSION,
        reserved: 0,
    }
}

fn status(a: &ReferenceAnswer) -> u32 {
    a.status
}

#[test]
fn not_ready_until_both_sides_arrived_and_a_solve_finished() {
    let now = Now::read();
    let mut s = state("rrwm");
    let q = by_id(1);
    assert_eq!(status(&s.answer(&q, &now)), AnswerStatus::NotReady as u32);
    s.state
        .accept_snapshot(
            Side::Robot,
            ROBOT_FEED,
            &header(Side::Robot, 1, 1, 4, &now),
            &entries(&ROBOT_IDS, 0.0),
            &now,
        )
        .unwrap();
    assert!(s.state.latest_pair().is_none());
    assert_eq!(status(&s.answer(&q, &now)), AnswerStatus::NotReady as u32);
    publish_both(&mut s, 2, &now);
    assert_eq!(
        status(&s.answer(&q, &now)),
        AnswerStatus::NotReady as u32,
        "accepted, not solved: the query never solves"
    );
    s.solve();
    assert_eq!(status(&s.answer(&q, &now)), AnswerStatus::Ok as u32);
}

#[test]
fn answers_by_id_with_position_confidence_and_alternatives() {
    let now = Now::read();
    let s = ready(&now);
    for (k, &h) in HUMAN_IDS.iter().enumerate() {
        let a = s.answer(&by_id(h), &now);
        assert_eq!(a.status, AnswerStatus::Ok as u32);
        assert_eq!(a.request_id, 9);
        assert_eq!(a.human_object_id, h);
        assert_eq!(a.robot_track_id, ROBOT_IDS[k]);
        assert_eq!(a.position, [WORLD[k][0] + 0.5, WORLD[k][1], WORLD[k][2]]);
        assert!(a.confidence > 0.0 && a.confidence <= 1.0);
        assert_eq!(a.alternative_count, 3);
        assert!(
            a.alternatives
                .iter()
                .all(|alt| alt.robot_track_id != a.robot_track_id)
        );
        assert_eq!((a.robot_sequence, a.human_sequence), (1, 1));
        // `paper` gives no motion: the human object's own position.
        assert_eq!(a.human_frame_position, WORLD[k]);
        assert_eq!(
            a.flags & !ReferenceAnswer::FLAG_SOLVED,
            ReferenceAnswer::FLAG_HUMAN_POSITION
        );
    }
    assert_eq!(s.state.solves(), 1, "answers never solve");
}

#[test]
fn answers_name_the_snapshots_their_solution_used_with_honest_ages() {
    let now = Now::read();
    let mut s = ready(&now);
    let later = now.after(Duration::from_millis(40));
    publish_moved(&mut s, 2, 0.01, &later);
    let asked = later.after(Duration::from_millis(5));
    let a = s.answer(&by_id(1), &asked);
    assert_eq!(
        (a.robot_sequence, a.human_sequence),
        (1, 1),
        "not solved yet"
    );
    assert_eq!((a.robot_age_us, a.human_age_us), (45_000, 45_000));
    let solved = s.solve();
    let a = s.answer(&by_id(1), &asked);
    assert_eq!((a.robot_sequence, a.human_sequence), (2, 2));
    assert_eq!((a.robot_age_us, a.human_age_us), (5_000, 5_000));
    let since = asked
        .instant
        .saturating_duration_since(solved.finished.instant);
    assert_eq!(a.solve_age_us, since.as_micros() as u64);
}

#[test]
fn answers_by_ray_and_latest_gesture() {
    let now = Now::read();
    let mut s = ready(&now);
    // From the origin toward object 3 of the human view (id 3).
    let dir = WORLD[2];
    let a = s.answer(&query(QueryKind::Ray, 0, [0.0; 3], dir), &now);
    assert_eq!(
        (a.status, a.human_object_id, a.robot_track_id, a.ray_age_us),
        (AnswerStatus::Ok as u32, 3, 20, 0)
    );

    let miss = s.answer(&query(QueryKind::Ray, 0, [0.0; 3], [0.0, -1.0, 0.0]), &now);
    assert_eq!(miss.status, AnswerStatus::NoMatch as u32);

    let latest = query(QueryKind::LatestGesture, 0, [0.0; 3], [0.0; 3]);
    let none = s.answer(&latest, &now);
    assert_eq!(none.status, AnswerStatus::NotReady as u32);
    let ray = pointing_at_object_4(&now);
    s.state.accept_ray(GESTURES, &ray, &now).unwrap();
    let a = s.answer(&latest, &now.after(Duration::from_millis(30)));
    assert_eq!(
        (a.status, a.human_object_id, a.robot_track_id, a.ray_age_us),
        (AnswerStatus::Ok as u32, 4, 10, 30_000)
    );
    let backwards = PointingRay { sequence: 1, ..ray };
    assert_eq!(
        s.state
            .accept_ray(GESTURES, &backwards, &now)
            .unwrap_err()
            .reason,
        RejectReason::SequenceBackwards
    );
    let zero = PointingRay {
        sequence: 2,
        direction: [0.0; 3],
        ..ray
    };
    assert_eq!(
        s.state
            .accept_ray(GESTURES, &zero, &now)
            .unwrap_err()
            .reason,
        RejectReason::BadRay
    );
}

#[test]
fn a_ray_older_than_its_maximum_age_makes_latest_gesture_answers_stale() {
    let now = Now::read();
    let mut s = ready(&now);
    s.state
        .accept_ray(GESTURES, &pointing_at_object_4(&now), &now)
        .unwrap();
    // Fresh snapshots keep coming; only the ray grows old.
    let later = now.after(Duration::from_millis(2500));
    publish_both(&mut s, 2, &later);
    s.solve();
    let latest = query(QueryKind::LatestGesture, 0, [0.0; 3], [0.0; 3]);
    let a = s.answer(&latest, &later);
    assert_eq!(a.status, AnswerStatus::Stale as u32, "ray max age 2000 ms");
    assert_eq!(
        (a.robot_track_id, a.ray_age_us),
        (10, 2_500_000),
        "stale, not wrong"
    );
    assert_eq!(s.answer(&by_id(4), &later).status, AnswerStatus::Ok as u32);
}

#[test]
fn bad_requests_are_answered_as_such() {
    let now = Now::read();
    let s = ready(&now);
    let unknown = s.answer(&by_id(99), &now);
    assert_eq!(unknown.status, AnswerStatus::BadRequest as u32);
    let zero_ray = s.answer(&query(QueryKind::Ray, 0, [0.0; 3], [0.0; 3]), &now);
    assert_eq!(zero_ray.status, AnswerStatus::BadRequest as u32);
    let mut odd = by_id(1);
    odd.kind = 17;
    assert_eq!(s.answer(&odd, &now).status, AnswerStatus::BadRequest as u32);
    odd = by_id(1);
    odd.schema_version = SCHEMA_VERSION + 1;
    assert_eq!(s.answer(&odd, &now).status, AnswerStatus::BadRequest as u32);
}

#[test]
fn a_silent_feed_makes_answers_stale_with_their_capture_age() {
    let start = Now::read();
    let mut s = ready(&start);
    let later = start.after(Duration::from_millis(800));
    let a = s.answer(&by_id(2), &later);
    assert_eq!(a.status, AnswerStatus::Stale as u32);
    assert_eq!(a.robot_track_id, 30, "stale, not wrong");
    assert_eq!(a.robot_age_us, 800_000);
    // Fresh snapshots, once solved, make it fresh again.
    publish_both(&mut s, 2, &later);
    s.solve();
    let a = s.answer(&by_id(2), &later);
    assert_eq!((a.status, a.robot_sequence), (AnswerStatus::Ok as u32, 2));
}

#[test]
fn a_snapshot_captured_long_before_it_arrived_is_stale_not_ok() {
    let now = Now::read();
    let mut s = state("paper");
    let captured = Now {
        unix_ns: now.unix_ns - 2_000_000_000,
        ..now
    };
    s.state
        .accept_snapshot(
            Side::Robot,
            ROBOT_FEED,
            &header(Side::Robot, 1, 1, 4, &captured),
            &entries(&ROBOT_IDS, 0.5),
            &now,
        )
        .unwrap();
    s.state
        .accept_snapshot(
            Side::Human,
            HUMAN_FEED,
            &header(Side::Human, 2, 1, 4, &now),
            &entries(&HUMAN_IDS, 0.0),
            &now,
        )
        .unwrap();
    s.solve();
    let a = s.answer(&by_id(1), &now);
    assert_eq!(
        (a.status, a.robot_age_us),
        (AnswerStatus::Stale as u32, 2_000_000)
    );
}

#[test]
fn stamps_from_the_future_or_absurdly_old_are_refused_and_counted() {
    let now = Now::read();
    let mut s = ready(&now);
    let at = |unix_ns| Now { unix_ns, ..now };
    let ahead = at(now.unix_ns + 5_000_000_000);
    let r = s.state.accept_snapshot(
        Side::Robot,
        ROBOT_FEED,
        &header(Side::Robot, 1, 2, 4, &ahead),
        &entries(&ROBOT_IDS, 0.5),
        &now,
    );
    assert_eq!(r.unwrap_err().reason, RejectReason::TimestampFuture);
    let hour_ago = at(now.unix_ns - 3_600_000_000_000);
    let r = s.state.accept_snapshot(
        Side::Human,
        HUMAN_FEED,
        &header(Side::Human, 2, 2, 4, &hour_ago),
        &entries(&HUMAN_IDS, 0.0),
        &now,
    );
    assert_eq!(r.unwrap_err().reason, RejectReason::TimestampTooOld);
    let old_ray = PointingRay {
        timestamp_ns: hour_ago.unix_ns,
        ..pointing_at_object_4(&now)
    };
    let r = s.state.accept_ray(GESTURES, &old_ray, &now);
    assert_eq!(r.unwrap_err().reason, RejectReason::TimestampTooOld);
    let rejections = s.state.rejections();
    assert_eq!(rejections.get(RejectReason::TimestampFuture), 1);
    assert_eq!(rejections.get(RejectReason::TimestampTooOld), 2);
    // A clock slightly ahead is within the skew allowed.
    let slightly = at(now.unix_ns + 50_000_000);
    s.state
        .accept_snapshot(
            Side::Robot,
            ROBOT_FEED,
            &header(Side::Robot, 1, 3, 4, &slightly),
            &entries(&ROBOT_IDS, 0.5),
            &now,
        )
        .unwrap();
}

#[test]
fn one_message_with_the_largest_sequence_locks_no_feed_out() {
    let now = Now::read();
    let mut s = ready(&now);
    let attacker: Origin = 666;
    // Another publisher in the feed's session: taken once, as its own.
    let hijack = header(Side::Robot, 1, u64::MAX, 4, &now);
    s.state
        .accept_snapshot(
            Side::Robot,
            attacker,
            &hijack,
            &entries(&ROBOT_IDS, 0.5),
            &now,
        )
        .unwrap();
    for sequence in 2..5 {
        s.state
            .accept_snapshot(
                Side::Robot,
                ROBOT_FEED,
                &header(Side::Robot, 1, sequence, 4, &now),
                &entries(&ROBOT_IDS, 0.5),
                &now,
            )
            .unwrap();
    }
    assert_eq!(s.state.snapshot(Side::Robot).unwrap().sequence, 4);
    // The feed's own port jumping there (a bridge forwarding it) is refused.
    let r = s.state.accept_snapshot(
        Side::Robot,
        ROBOT_FEED,
        &hijack,
        &entries(&ROBOT_IDS, 0.5),
        &now,
    );
    assert_eq!(r.unwrap_err().reason, RejectReason::SequenceJump);
    // Rays alike.
    let ray = pointing_at_object_4(&now);
    s.state.accept_ray(GESTURES, &ray, &now).unwrap();
    let hijacked = PointingRay {
        sequence: u64::MAX,
        direction: WORLD[0],
        ..ray
    };
    s.state.accept_ray(attacker, &hijacked, &now).unwrap();
    let next = PointingRay { sequence: 2, ..ray };
    s.state.accept_ray(GESTURES, &next, &now).unwrap();
    s.solve();
    let a = s.answer(
        &query(QueryKind::LatestGesture, 0, [0.0; 3], [0.0; 3]),
        &now,
    );
    assert_eq!((a.status, a.human_object_id), (AnswerStatus::Ok as u32, 4));
}

#[test]
fn rejected_snapshots_are_counted_and_the_last_good_one_stays() {
    let now = Now::read();
    let mut s = ready(&now);
    let mut bad = entries(&ROBOT_IDS, 0.5);
    bad[0].position[1] = f32::NAN;
    let robot = |s: &mut Rig, h: &SnapshotHeader, e: &[ObjectEntry]| {
        s.state.accept_snapshot(Side::Robot, ROBOT_FEED, h, e, &now)
    };
    let r = robot(&mut s, &header(Side::Robot, 1, 2, 4, &now), &bad).unwrap_err();
    assert_eq!(r.reason, RejectReason::NonFinitePosition);
    assert!(r.detail.contains("object id 40"), "{}", r.detail);

    let good = entries(&ROBOT_IDS, 0.5);
    let r = robot(&mut s, &header(Side::Robot, 1, 1, 4, &now), &good);
    assert_eq!(r.unwrap_err().reason, RejectReason::SequenceBackwards);

    let mut other_dim = header(Side::Robot, 1, 3, 4, &now);
    other_dim.feature_dim = 5;
    let r = robot(&mut s, &other_dim, &good);
    assert_eq!(r.unwrap_err().reason, RejectReason::FeatureDimOtherSide);

    let r = robot(&mut s, &header(Side::Robot, 1, 4, 9, &now), &good);
    assert_eq!(r.unwrap_err().reason, RejectReason::CountExceedsSlice);

    assert_eq!(s.state.rejections().total(), 4);
    assert_eq!(
        s.state.snapshot(Side::Robot).unwrap().sequence,
        1,
        "the last good snapshot stays"
    );
    let a = s.answer(&by_id(1), &now);
    assert_eq!((a.status, a.robot_track_id), (AnswerStatus::Ok as u32, 40));

    // A restarted feed (new port, new session) may start its sequence again.
    s.state
        .accept_snapshot(
            Side::Robot,
            ROBOT_FEED + 1,
            &header(Side::Robot, 77, 1, 4, &now),
            &good,
            &now,
        )
        .unwrap();
    assert_eq!(s.state.snapshot(Side::Robot).unwrap().session, 77);
}

#[test]
fn an_up_vector_is_kept_with_its_snapshot_and_a_bad_one_counted_as_bad_up() {
    let now = Now::read();
    let mut s = ready(&now);
    assert_eq!(s.state.snapshot(Side::Human).unwrap().graph.up(), None);
    let good = entries(&HUMAN_IDS, 0.0);
    let human = |s: &mut Rig, sequence: u64, up: Option<[f32; 3]>| {
        let mut h = header(Side::Human, 2, sequence, 4, &now);
        h.set_up(up);
        s.state
            .accept_snapshot(Side::Human, HUMAN_FEED, &h, &good, &now)
    };
    human(&mut s, 2, Some([0.0, -2.0, 0.0])).unwrap();
    let up = s.state.snapshot(Side::Human).unwrap().graph.up();
    assert_eq!(up, Some(nalgebra::Vector3::new(0.0, -1.0, 0.0)));

    let r = human(&mut s, 3, Some([0.0, 0.0, 0.0])).unwrap_err();
    assert_eq!(r.reason, RejectReason::BadUp);
    assert!(r.detail.contains("up is [0.0, 0.0, 0.0]"), "{}", r.detail);
    let r = human(&mut s, 4, Some([f32::NAN, 1.0, 0.0])).unwrap_err();
    assert_eq!(r.reason, RejectReason::BadUp);
    assert_eq!(s.state.rejections().get(RejectReason::BadUp), 2);
    assert_eq!(s.state.rejections().total(), 2);
    let kept = s.state.snapshot(Side::Human).unwrap();
    assert_eq!((kept.sequence, kept.graph.up()), (2, up));

    // A snapshot that says nothing of gravity takes the up vector away.
    human(&mut s, 5, None).unwrap();
    assert_eq!(s.state.snapshot(Side::Human).unwrap().graph.up(), None);
}

/// Stats readers index `MatcherStats::rejected` by reason: a new reason
/// goes at the end, and every earlier one keeps its slot.
#[test]
fn reject_reasons_keep_their_counter_slots() {
    let names: Vec<&str> = RejectReason::ALL.iter().map(|r| r.name()).collect();
    assert_eq!(names[8], "duplicate_id");
    assert_eq!(names[19], "query_over_rate");
    assert_eq!(names.last(), Some(&"bad_up"));
    for (index, reason) in RejectReason::ALL.into_iter().enumerate() {
        assert_eq!(reason as usize, index, "{reason}");
    }
}

#[test]
fn unknown_method_is_refused() {
    assert!(ReferenceState::new(&settings("magic"), Limits::default()).is_err());
    assert!(Solver::new(&settings("magic"), Params::default()).is_err());
}

#[test]
fn solves_and_the_solved_flag_count_real_solves() {
    let now = Now::read();
    let mut s = ready(&now);
    let first = s.answer(&by_id(1), &now);
    assert_eq!(first.status, AnswerStatus::Ok as u32);
    assert!(first.solved(), "the first solution is a real solve");
    assert_eq!(s.state.solves(), 1);
    // New sequences of the same objects: nothing to solve, the solution is
    // carried over and names the new snapshots.
    publish_both(&mut s, 2, &now);
    let carried = s.solve();
    assert!(!carried.real);
    let a = s.answer(&by_id(1), &now);
    assert!(!a.solved());
    assert_eq!((a.robot_sequence, s.state.solves()), (2, 1));
    // Objects that moved need a real solve.
    publish_moved(&mut s, 3, 0.02, &now);
    assert!(s.solve().real);
    assert!(s.answer(&by_id(1), &now).solved());
    assert_eq!(s.state.solves(), 2);
    let bad = s.answer(&by_id(99), &now);
    assert_eq!(bad.status, AnswerStatus::BadRequest as u32);
}

#[test]
fn the_default_method_answers_with_its_calibrated_confidence_and_the_mapped_position() {
    let now = Now::read();
    let settings = MatcherSettings::default();
    assert_eq!(settings.method, "rigid");
    assert!(settings.ambiguity_threshold > 0.0);
    let s = ready_with(settings, &now);
    let motion = s.state.solution().unwrap().solution.motion;
    assert!(motion.is_some(), "rigid gives its motion");
    for (k, &h) in HUMAN_IDS.iter().enumerate() {
        let a = s.answer(&by_id(h), &now);
        assert_eq!(a.status, AnswerStatus::Ok as u32, "human object {h}");
        assert_eq!(a.robot_track_id, ROBOT_IDS[k]);
        assert!(
            a.confidence >= 0.5 && a.confidence <= 1.0,
            "{}",
            a.confidence
        );
        let both =
            ReferenceAnswer::FLAG_HUMAN_POSITION | ReferenceAnswer::FLAG_HUMAN_POSITION_FROM_MOTION;
        assert_eq!(a.flags & both, both);
        // The robot object taken back through the motion lands on the
        // human object (the views differ by a shift).
        for (got, want) in a.human_frame_position.iter().zip(WORLD[k]) {
            assert!(
                (got - want).abs() < 1e-3,
                "human {h}: {:?}",
                a.human_frame_position
            );
        }
    }
}

#[test]
fn the_published_decision_says_what_answers_say() {
    let now = Now::read();
    for method in ["rigid", "paper"] {
        let s = ready_with(settings(method), &now);
        let solved = s.state.solution().unwrap();
        let header = decision_header(solved, method);
        assert_eq!(
            (
                header.robot_sequence,
                header.human_sequence,
                header.solve_index
            ),
            (1, 1, 1)
        );
        assert_eq!(header.robot_timestamp_ns, now.unix_ns);
        let motion = header.flags & DecisionHeader::FLAG_MOTION != 0;
        assert_eq!(motion, method == "rigid", "{method}");
        assert_eq!(decision_len(solved), HUMAN_IDS.len());
        for (row, &h) in HUMAN_IDS.iter().enumerate() {
            let entry = decision_entry(solved, row, &settings(method).ok_rule());
            let a = s.answer(&by_id(h), &now);
            assert_eq!(entry.human_track_id, h);
            assert_eq!(
                (entry.robot_track_id, entry.status),
                (a.robot_track_id, a.status)
            );
            assert_eq!(entry.confidence, a.confidence);
            assert_eq!(entry.flags, DecisionEntry::FLAG_PARTNER);
        }
    }
}

#[test]
fn answers_below_the_ambiguity_threshold_are_ambiguous_with_alternatives() {
    let now = Now::read();
    let q = by_id(HUMAN_IDS[0]);
    let at = |threshold: f64| {
        let settings = MatcherSettings {
            ambiguity_threshold: threshold,
            ..settings("paper")
        };
        ready_with(settings, &now).answer(&q, &now)
    };
    let sure = at(0.0);
    assert_eq!(sure.status, AnswerStatus::Ok as u32);
    // The paper's confidence is a row share, below 1 with four columns.
    assert!(sure.confidence < 1.0);
    let unsure = at(f64::from(sure.confidence) + 1e-3);
    assert_eq!(unsure.status, AnswerStatus::Ambiguous as u32);
    assert_eq!(unsure.robot_track_id, sure.robot_track_id);
    assert_eq!(unsure.alternative_count, 3);
    assert!(
        unsure
            .alternatives
            .iter()
            .all(|alt| alt.robot_track_id != 0 && alt.robot_track_id != unsure.robot_track_id)
    );
}

#[global_allocator]
static ALLOCATOR: vref_alloc_count::Counting = vref_alloc_count::Counting;

#[test]
fn cached_answers_allocate_nothing() {
    for method in ["rigid", "paper"] {
        let now = Now::read();
        let mut s = ready_with(settings(method), &now);
        let ray = pointing_at_object_4(&now);
        s.state.accept_ray(GESTURES, &ray, &now).unwrap();
        let queries = [
            by_id(2),
            query(QueryKind::Ray, 0, [0.0; 3], WORLD[2]),
            query(QueryKind::LatestGesture, 0, [0.0; 3], [0.0; 3]),
            by_id(99),
        ];
        // The solve allocates, on the solver's side of the hand-off ...
        publish_moved(&mut s, 2, 0.01, &now);
        let (_, solving) = vref_alloc_count::allocations_in(|| s.solve());
        assert!(solving > 0, "{method}: the solve itself allocates");
        // ... and no query does, of any kind, nor picking up the solution.
        let newest = Arc::new(s.solver.solve(&s.state.latest_pair().unwrap()).unwrap());
        let (retired, installing) = vref_alloc_count::allocations_in(|| s.state.install(newest));
        assert_eq!(installing, 0, "{method}: installing a solution allocated");
        drop(retired);
        for q in &queries {
            let asked = Now::read();
            let (answer, allocations) = vref_alloc_count::allocations_in(|| s.answer(q, &asked));
            assert_ne!(answer.status, AnswerStatus::NotReady as u32);
            assert_eq!(
                allocations, 0,
                "{method}: query kind {} allocated {allocations} times",
                q.kind
            );
        }
    }
}

#[test]
fn a_ray_between_two_objects_halves_the_confidence_of_the_one_it_takes() {
    let now = Now::read();
    let s = ready(&now);
    let unit = |v: [f32; 3]| {
        let n = v.iter().map(|x| x * x).sum::<f32>().sqrt();
        v.map(|x| x / n)
    };
    let (a, b) = (unit(WORLD[0]), unit(WORLD[3]));
    // The bisector of the directions to objects 1 and 4, both 0.12 rad
    // off it and inside a 0.15 rad cone (object 3 is 0.19 rad off): the
    // pointing is split in two.
    let between = [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
    let mut q = query(QueryKind::Ray, 0, [0.0; 3], between);
    q.cone_half_angle = 0.15;
    let split = s.answer(&q, &now);
    let alone = s.answer(&by_id(split.human_object_id), &now);
    assert!([1, 4].contains(&split.human_object_id), "{split:?}");
    assert_eq!(split.robot_track_id, alone.robot_track_id);
    let half = 0.5 * alone.confidence;
    assert!(
        (split.confidence - half).abs() < 1e-3,
        "{split:?} {alone:?}"
    );
    let expected = if half < 0.5 {
        AnswerStatus::Ambiguous
    } else {
        AnswerStatus::Ok
    };
    assert_eq!(split.status, expected as u32);

    // Straight at object 4: object 1, 0.24 rad off, is outside the cone.
    let mut q = query(QueryKind::Ray, 0, [0.0; 3], WORLD[3]);
    q.cone_half_angle = 0.15;
    let straight = s.answer(&q, &now);
    assert_eq!(straight.human_object_id, 4);
    assert_eq!(straight.confidence, s.answer(&by_id(4), &now).confidence);
}

/// A snapshot with `dim` feature values of `side`'s feed.
fn with_dim(
    s: &mut Rig,
    side: Side,
    sequence: u64,
    dim: u32,
    now: &Now,
) -> Result<(), RejectReason> {
    let (origin, session, ids, shift) = match side {
        Side::Robot => (ROBOT_FEED, 1, &ROBOT_IDS, 0.5),
        Side::Human => (HUMAN_FEED, 2, &HUMAN_IDS, 0.0),
    };
    let mut h = header(side, session, sequence, 4, now);
    h.feature_dim = dim;
    s.state
        .accept_snapshot(side, origin, &h, &entries(ids, shift), now)
        .map(drop)
        .map_err(|r| r.reason)
}

/// Issue 40, case 1: both feeds replaced by a source with another feature
/// length. Before, each side was refused against the other's old
/// snapshot for as long as the matcher ran.
#[test]
fn both_sides_changing_their_feature_length_are_taken_at_once() {
    let now = Now::read();
    let mut s = ready(&now);
    assert_eq!(
        with_dim(&mut s, Side::Robot, 2, 5, &now),
        Err(RejectReason::FeatureDimOtherSide)
    );
    // The human side agrees: taken, and the robot's old snapshot dropped
    // (its features cannot be compared with the new ones).
    with_dim(&mut s, Side::Human, 2, 5, &now).unwrap();
    assert!(s.state.snapshot(Side::Robot).is_none());
    assert!(s.state.latest_pair().is_none());
    with_dim(&mut s, Side::Robot, 3, 5, &now).unwrap();
    s.solve();
    let a = s.answer(&by_id(1), &now);
    assert_eq!((a.status, a.robot_track_id), (AnswerStatus::Ok as u32, 40));
}

/// One side's source replaced while the other side's feed is gone: taken
/// once that side has sent nothing for the grace; not while it is live.
#[test]
fn one_side_changing_its_feature_length_waits_for_the_grace_if_the_other_is_live() {
    let now = Now::read();
    let settings = MatcherSettings {
        feature_dim_grace_ms: 300,
        ..settings("paper")
    };
    let mut s = ready_with(settings, &now);
    let at = |ms: u64| Now {
        instant: now.instant + Duration::from_millis(ms),
        unix_ns: now.unix_ns + ms * 1_000_000,
    };
    assert_eq!(
        with_dim(&mut s, Side::Robot, 2, 5, &at(100)),
        Err(RejectReason::FeatureDimOtherSide)
    );
    // The human feed is live: its snapshot keeps the length in force.
    with_dim(&mut s, Side::Human, 2, 4, &at(200)).unwrap();
    assert_eq!(
        with_dim(&mut s, Side::Robot, 3, 5, &at(400)),
        Err(RejectReason::FeatureDimOtherSide)
    );
    // Silent for the grace: the new length is taken.
    with_dim(&mut s, Side::Robot, 4, 5, &at(500)).unwrap();
    assert!(s.state.snapshot(Side::Human).is_none());
    assert_eq!(
        s.state.snapshot(Side::Robot).unwrap().graph.feature_dim(),
        5
    );
    // One stray message of the old length, however long after: refused
    // (a new source sends for the grace).
    assert_eq!(with_dim(&mut s, Side::Robot, 5, 5, &at(5000)), Ok(()));
    assert_eq!(
        with_dim(&mut s, Side::Human, 3, 4, &at(9000)),
        Err(RejectReason::FeatureDimOtherSide)
    );
}
