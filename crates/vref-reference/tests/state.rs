#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::time::{Duration, Instant};

use vref_match::Params;
use vref_reference::{MatcherSettings, ReferenceState, RejectReason};
use vref_scene::{Limits, Side};
use vref_wire::{
    AnswerStatus, FRAME_NAME_LEN, MAX_FEATURE_DIM, ObjectEntry, PointingRay, QueryKind,
    ReferenceAnswer, ReferenceQuery, SCHEMA_VERSION, SideCode, SnapshotHeader,
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

fn header(side: Side, session: u64, sequence: u64, count: usize) -> SnapshotHeader {
    SnapshotHeader {
        session,
        sequence,
        timestamp_ns: 0,
        schema_version: SCHEMA_VERSION,
        side: if side == Side::Robot {
            SideCode::Robot as u32
        } else {
            SideCode::Human as u32
        },
        object_count: count as u32,
        feature_dim: 4,
        frame_name: [0; FRAME_NAME_LEN],
    }
}

const HUMAN_IDS: [u64; 4] = [1, 2, 3, 4];
const ROBOT_IDS: [u64; 4] = [40, 30, 20, 10];

fn settings(method: &str) -> MatcherSettings {
    MatcherSettings {
        method: method.to_owned(),
        ..MatcherSettings::default()
    }
}

fn state(method: &str) -> ReferenceState {
    ReferenceState::new(&settings(method), Params::default(), Limits::default()).unwrap()
}

/// Both views of the four objects, snapshot `sequence` of each feed; the
/// robot sees the table shifted by 0.5 m.
fn publish_both(s: &mut ReferenceState, sequence: u64, now: Instant) {
    s.accept_snapshot(
        Side::Robot,
        &header(Side::Robot, 1, sequence, 4),
        &entries(&ROBOT_IDS, 0.5),
        now,
    )
    .unwrap();
    s.accept_snapshot(
        Side::Human,
        &header(Side::Human, 2, sequence, 4),
        &entries(&HUMAN_IDS, 0.0),
        now,
    )
    .unwrap();
}

fn ready_with(settings: MatcherSettings, now: Instant) -> ReferenceState {
    let mut s = ReferenceState::new(&settings, Params::default(), Limits::default()).unwrap();
    publish_both(&mut s, 1, now);
    s
}

fn ready(now: Instant) -> ReferenceState {
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

/// The person's first gesture, from the origin toward object 4 of the
/// human view.
fn pointing_at_object_4() -> PointingRay {
    PointingRay {
        session: 5,
        sequence: 1,
        timestamp_ns: 0,
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
fn not_ready_until_both_sides_arrived() {
    let now = Instant::now();
    let mut s = state("rrwm");
    let q = query(QueryKind::HumanObject, 1, [0.0; 3], [0.0; 3]);
    assert_eq!(status(&s.answer(&q, now)), AnswerStatus::NotReady as u32);
    s.accept_snapshot(
        Side::Robot,
        &header(Side::Robot, 1, 1, 4),
        &entries(&ROBOT_IDS, 0.0),
        now,
    )
    .unwrap();
    assert_eq!(status(&s.answer(&q, now)), AnswerStatus::NotReady as u32);
}

#[test]
fn answers_by_id_with_position_confidence_and_alternatives() {
    let now = Instant::now();
    let mut s = ready(now);
    for (k, &h) in HUMAN_IDS.iter().enumerate() {
        let a = s.answer(&query(QueryKind::HumanObject, h, [0.0; 3], [0.0; 3]), now);
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
    }
    assert_eq!(
        s.solves(),
        1,
        "answers after the first come from the cached solution"
    );
}

#[test]
fn answers_by_ray_and_latest_gesture() {
    let now = Instant::now();
    let mut s = ready(now);
    // From the origin toward object 3 of the human view (id 3).
    let dir = WORLD[2];
    let a = s.answer(&query(QueryKind::Ray, 0, [0.0; 3], dir), now);
    assert_eq!(
        (a.status, a.human_object_id, a.robot_track_id),
        (AnswerStatus::Ok as u32, 3, 20)
    );

    let miss = s.answer(&query(QueryKind::Ray, 0, [0.0; 3], [0.0, -1.0, 0.0]), now);
    assert_eq!(miss.status, AnswerStatus::NoMatch as u32);

    let none = s.answer(&query(QueryKind::LatestGesture, 0, [0.0; 3], [0.0; 3]), now);
    assert_eq!(none.status, AnswerStatus::NotReady as u32);
    let ray = pointing_at_object_4();
    s.accept_ray(&ray).unwrap();
    let a = s.answer(&query(QueryKind::LatestGesture, 0, [0.0; 3], [0.0; 3]), now);
    assert_eq!(
        (a.status, a.human_object_id, a.robot_track_id),
        (AnswerStatus::Ok as u32, 4, 10)
    );
    let backwards = PointingRay { sequence: 1, ..ray };
    assert_eq!(
        s.accept_ray(&backwards).unwrap_err().reason,
        RejectReason::SequenceBackwards
    );
    let zero = PointingRay {
        sequence: 2,
        direction: [0.0; 3],
        ..ray
    };
    assert_eq!(
        s.accept_ray(&zero).unwrap_err().reason,
        RejectReason::BadRay
    );
}

#[test]
fn bad_requests_are_answered_as_such() {
    let now = Instant::now();
    let mut s = ready(now);
    let unknown = s.answer(&query(QueryKind::HumanObject, 99, [0.0; 3], [0.0; 3]), now);
    assert_eq!(unknown.status, AnswerStatus::BadRequest as u32);
    let zero_ray = s.answer(&query(QueryKind::Ray, 0, [0.0; 3], [0.0; 3]), now);
    assert_eq!(zero_ray.status, AnswerStatus::BadRequest as u32);
    let mut odd = query(QueryKind::HumanObject, 1, [0.0; 3], [0.0; 3]);
    odd.kind = 17;
    assert_eq!(s.answer(&odd, now).status, AnswerStatus::BadRequest as u32);
    odd = query(QueryKind::HumanObject, 1, [0.0; 3], [0.0; 3]);
    odd.schema_version = 3;
    assert_eq!(s.answer(&odd, now).status, AnswerStatus::BadRequest as u32);
}

#[test]
fn a_silent_feed_makes_answers_stale_with_their_age() {
    let start = Instant::now();
    let mut s = ready(start);
    let later = start + Duration::from_millis(800);
    let a = s.answer(&query(QueryKind::HumanObject, 2, [0.0; 3], [0.0; 3]), later);
    assert_eq!(a.status, AnswerStatus::Stale as u32);
    assert_eq!(a.robot_track_id, 30, "stale, not wrong");
    assert_eq!(a.robot_age_us, 800_000);
    // Fresh snapshots make it fresh again.
    publish_both(&mut s, 2, later);
    let a = s.answer(&query(QueryKind::HumanObject, 2, [0.0; 3], [0.0; 3]), later);
    assert_eq!((a.status, a.robot_sequence), (AnswerStatus::Ok as u32, 2));
}

#[test]
fn rejected_snapshots_are_counted_and_the_last_good_one_stays() {
    let now = Instant::now();
    let mut s = ready(now);
    let mut bad = entries(&ROBOT_IDS, 0.5);
    bad[0].position[1] = f32::NAN;
    let r = s
        .accept_snapshot(Side::Robot, &header(Side::Robot, 1, 2, 4), &bad, now)
        .unwrap_err();
    assert_eq!(r.reason, RejectReason::NonFinitePosition);
    assert!(r.detail.contains("object id 40"), "{}", r.detail);

    let r = s.accept_snapshot(
        Side::Robot,
        &header(Side::Robot, 1, 1, 4),
        &entries(&ROBOT_IDS, 0.5),
        now,
    );
    assert_eq!(r.unwrap_err().reason, RejectReason::SequenceBackwards);

    let mut other_dim = header(Side::Robot, 1, 3, 4);
    other_dim.feature_dim = 5;
    let r = s.accept_snapshot(Side::Robot, &other_dim, &entries(&ROBOT_IDS, 0.5), now);
    assert_eq!(r.unwrap_err().reason, RejectReason::FeatureDimOtherSide);

    let r = s.accept_snapshot(
        Side::Robot,
        &header(Side::Robot, 1, 4, 9),
        &entries(&ROBOT_IDS, 0.5),
        now,
    );
    assert_eq!(r.unwrap_err().reason, RejectReason::CountExceedsSlice);

    assert_eq!(s.rejections().total(), 4);
    assert_eq!(
        s.snapshot(Side::Robot).unwrap().sequence,
        1,
        "the last good snapshot stays"
    );
    let a = s.answer(&query(QueryKind::HumanObject, 1, [0.0; 3], [0.0; 3]), now);
    assert_eq!((a.status, a.robot_track_id), (AnswerStatus::Ok as u32, 40));

    // A restarted feed (new session) may start its sequence again.
    s.accept_snapshot(
        Side::Robot,
        &header(Side::Robot, 77, 1, 4),
        &entries(&ROBOT_IDS, 0.5),
        now,
    )
    .unwrap();
    assert_eq!(s.snapshot(Side::Robot).unwrap().session, 77);
}

#[test]
fn unknown_method_is_refused() {
    assert!(ReferenceState::new(&settings("magic"), Params::default(), Limits::default()).is_err());
}

#[test]
fn answers_say_whether_they_needed_a_solve() {
    let now = Instant::now();
    let mut s = ready(now);
    let q = query(QueryKind::HumanObject, 1, [0.0; 3], [0.0; 3]);
    let first = s.answer(&q, now);
    assert_eq!(first.status, AnswerStatus::Ok as u32);
    assert!(first.solved(), "the first answer solves");
    assert_eq!(first.flags, ReferenceAnswer::FLAG_SOLVED);
    let cached = s.answer(&q, now);
    assert!(!cached.solved(), "the same snapshots: cached");
    assert_eq!(cached.flags, 0);
    s.accept_snapshot(
        Side::Human,
        &header(Side::Human, 2, 2, 4),
        &entries(&HUMAN_IDS, 0.0),
        now,
    )
    .unwrap();
    assert!(s.answer(&q, now).solved(), "a new snapshot needs a solve");
    assert!(!s.answer(&q, now).solved());
    let bad = s.answer(&query(QueryKind::HumanObject, 99, [0.0; 3], [0.0; 3]), now);
    assert_eq!(bad.status, AnswerStatus::BadRequest as u32);
    assert!(!bad.solved());
    assert_eq!(s.solves(), 2);
}

#[test]
fn the_default_method_answers_with_its_calibrated_confidence() {
    let now = Instant::now();
    let settings = MatcherSettings::default();
    assert_eq!(settings.method, "rigid");
    assert!(settings.ambiguity_threshold > 0.0);
    let mut s = ready_with(settings, now);
    for (k, &h) in HUMAN_IDS.iter().enumerate() {
        let a = s.answer(&query(QueryKind::HumanObject, h, [0.0; 3], [0.0; 3]), now);
        assert_eq!(a.status, AnswerStatus::Ok as u32, "human object {h}");
        assert_eq!(a.robot_track_id, ROBOT_IDS[k]);
        assert!(
            a.confidence >= 0.5 && a.confidence <= 1.0,
            "{}",
            a.confidence
        );
    }
}

#[test]
fn answers_below_the_ambiguity_threshold_are_ambiguous_with_alternatives() {
    let now = Instant::now();
    let q = query(QueryKind::HumanObject, HUMAN_IDS[0], [0.0; 3], [0.0; 3]);
    let at = |threshold: f64| {
        let settings = MatcherSettings {
            ambiguity_threshold: threshold,
            ..settings("paper")
        };
        ready_with(settings, now).answer(&q, now)
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

/// Counts heap allocations made by the thread that enabled counting, so
/// the query path's "no allocation" can be checked while the test
/// harness's other threads allocate as they like.
mod counting {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;
    use std::sync::atomic::{AtomicUsize, Ordering};

    pub struct Counting;

    static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

    thread_local! {
        static ENABLED: Cell<bool> = const { Cell::new(false) };
    }

    fn note() {
        // `try_with`: the allocator may run while thread locals are torn down.
        if ENABLED.try_with(Cell::get).unwrap_or(false) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
    }

    // SAFETY: every call is passed on unchanged to the system allocator;
    // the counter neither allocates nor touches the memory.
    #[allow(unsafe_code)]
    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
            note();
            // SAFETY: the caller's contract is System's contract.
            unsafe { System.alloc(layout) }
        }
        unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
            note();
            // SAFETY: as above.
            unsafe { System.alloc_zeroed(layout) }
        }
        unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
            note();
            // SAFETY: as above.
            unsafe { System.realloc(ptr, layout, new_size) }
        }
        unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
            // SAFETY: as above.
            unsafe { System.dealloc(ptr, layout) }
        }
    }

    /// Allocations made by this thread while `f` ran.
    pub fn allocations_in<T>(f: impl FnOnce() -> T) -> (T, usize) {
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        ENABLED.with(|e| e.set(true));
        let value = f();
        ENABLED.with(|e| e.set(false));
        (value, ALLOCATIONS.load(Ordering::Relaxed) - before)
    }
}

#[global_allocator]
static ALLOCATOR: counting::Counting = counting::Counting;

#[test]
fn cached_answers_allocate_nothing() {
    for method in ["rigid", "paper"] {
        let now = Instant::now();
        let mut s = ready_with(settings(method), now);
        let ray = pointing_at_object_4();
        s.accept_ray(&ray).unwrap();
        let queries = [
            query(QueryKind::HumanObject, 2, [0.0; 3], [0.0; 3]),
            query(QueryKind::Ray, 0, [0.0; 3], WORLD[2]),
            query(QueryKind::LatestGesture, 0, [0.0; 3], [0.0; 3]),
            query(QueryKind::HumanObject, 99, [0.0; 3], [0.0; 3]),
        ];
        let (first, solving) = counting::allocations_in(|| s.answer(&queries[0], now));
        assert!(first.solved());
        assert!(solving > 0, "{method}: the solve itself allocates");
        for q in &queries {
            let (answer, allocations) = counting::allocations_in(|| s.answer(q, now));
            assert!(!answer.solved(), "{method}: cached");
            assert_eq!(
                allocations, 0,
                "{method}: query kind {} allocated {allocations} times",
                q.kind
            );
        }
    }
}
