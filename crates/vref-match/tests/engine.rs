#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

//! The incremental engine: answers equal to a fresh solve (exact tier),
//! updates by track id, and the live tier's shortcuts.

use vref_match::engine::{Change, Engine};
use vref_match::{MatchError, Method, Params, Problem, Solution, Tier, solve};
use vref_scene::{Limits, SceneGraph, SceneObject, Side};
use vref_sim::RigidScene;

fn fresh(human: &SceneGraph, robot: &SceneGraph, method: Method) -> Solution {
    let problem = Problem::new(human, robot, Params::default().beta).unwrap();
    solve(method, &problem, &Params::default()).unwrap()
}

fn subset(graph: &SceneGraph, keep: impl Fn(usize) -> bool, reverse: bool) -> SceneGraph {
    let mut objects: Vec<SceneObject> = graph
        .objects()
        .iter()
        .enumerate()
        .filter(|(k, _)| keep(*k))
        .map(|(_, o)| o.clone())
        .collect();
    if reverse {
        objects.reverse();
    }
    SceneGraph::new(objects, None, &Limits::default()).unwrap()
}

fn assert_same(engine: &mut Engine, human: &SceneGraph, robot: &SceneGraph, method: Method) {
    let expected = fresh(human, robot, method);
    let (got, human_ids, robot_ids) = engine.solve().unwrap();
    assert_eq!(
        human_ids,
        human.objects().iter().map(|o| o.id).collect::<Vec<_>>()
    );
    assert_eq!(
        robot_ids,
        robot.objects().iter().map(|o| o.id).collect::<Vec<_>>()
    );
    assert_eq!(got.assignment, expected.assignment);
    assert_eq!(got.iterations, expected.iterations);
    let worst = got
        .soft
        .iter()
        .zip(&expected.soft)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "soft answers differ by {worst}");
}

#[test]
fn exact_engine_equals_a_fresh_solve_after_every_kind_of_update() {
    for method in [Method::Paper, Method::Rrwm, Method::Sm, Method::Appearance] {
        let scene = RigidScene::new(12, 7).unwrap();
        let mut engine = Engine::new(method, Tier::Exact, Params::default()).unwrap();
        engine.update(Side::Human, &scene.human).unwrap();
        engine.update(Side::Robot, &scene.robot).unwrap();
        assert_same(&mut engine, &scene.human, &scene.robot, method);

        // One object moved.
        let moved = scene.moved(4, 11).unwrap();
        let change = engine.update(Side::Human, &moved.human).unwrap();
        assert_eq!((change.changed, change.kept), (1, 11));
        assert_same(&mut engine, &moved.human, &scene.robot, method);

        // Objects removed on one side, the other side reordered, between
        // two solves.
        let fewer = subset(&moved.human, |k| k % 5 != 2, false);
        let reordered = subset(&scene.robot, |_| true, true);
        engine.update(Side::Human, &fewer).unwrap();
        let change = engine.update(Side::Robot, &reordered).unwrap();
        assert_eq!(
            change,
            Change {
                added: 0,
                removed: 0,
                changed: 0,
                kept: 12
            }
        );
        assert_same(&mut engine, &fewer, &reordered, method);

        // The removed objects come back.
        engine.update(Side::Human, &moved.human).unwrap();
        assert_same(&mut engine, &moved.human, &reordered, method);
    }
}

#[test]
fn updates_are_counted_by_track_id() {
    let scene = RigidScene::new(8, 3).unwrap();
    let mut engine = Engine::new(Method::Paper, Tier::Live, Params::default()).unwrap();
    let first = engine.update(Side::Robot, &scene.robot).unwrap();
    assert_eq!(
        first,
        Change {
            added: 8,
            removed: 0,
            changed: 0,
            kept: 0
        }
    );
    let same = engine.update(Side::Robot, &scene.robot).unwrap();
    assert!(!same.any());
    let fewer = subset(&scene.robot, |k| k < 5, false);
    let change = engine.update(Side::Robot, &fewer).unwrap();
    assert_eq!(
        change,
        Change {
            added: 0,
            removed: 3,
            changed: 0,
            kept: 5
        }
    );
}

#[test]
fn a_solve_is_reused_until_a_view_changes() {
    let scene = RigidScene::new(10, 2).unwrap();
    let mut engine = Engine::new(Method::Paper, Tier::Live, Params::default()).unwrap();
    assert!(matches!(engine.solve(), Err(MatchError::EmptyGraph { .. })));
    engine.update(Side::Human, &scene.human).unwrap();
    engine.update(Side::Robot, &scene.robot).unwrap();
    assert!(engine.is_dirty());
    engine.solve().unwrap();
    assert!(!engine.is_dirty());
    engine.update(Side::Robot, &scene.robot).unwrap();
    assert!(!engine.is_dirty(), "an identical snapshot changes nothing");
    engine
        .update(Side::Human, &scene.moved(1, 1).unwrap().human)
        .unwrap();
    assert!(engine.is_dirty());
}

#[test]
fn bad_graphs_are_refused_and_change_nothing() {
    let scene = RigidScene::new(6, 1).unwrap();
    let mut engine = Engine::new(Method::Paper, Tier::Exact, Params::default()).unwrap();
    engine.update(Side::Human, &scene.human).unwrap();
    engine.update(Side::Robot, &scene.robot).unwrap();
    let before = engine.solve().unwrap().0.clone();

    let objects = scene.robot.objects().to_vec();
    let ids = [objects[0].id, objects[1].id];
    let with_edges = SceneGraph::new(objects, Some(vec![ids]), &Limits::default()).unwrap();
    assert_eq!(
        engine.update(Side::Robot, &with_edges),
        Err(MatchError::EdgeListInEngine)
    );
    let short: Vec<SceneObject> = scene
        .robot
        .objects()
        .iter()
        .map(|o| {
            SceneObject::new(
                o.id,
                [o.position.x, o.position.y, o.position.z],
                vec![1.0; 3],
            )
        })
        .collect();
    let short = SceneGraph::new(short, None, &Limits::default()).unwrap();
    assert!(matches!(
        engine.update(Side::Robot, &short),
        Err(MatchError::FeatureDimsDiffer { .. })
    ));
    assert!(!engine.is_dirty());
    assert_eq!(engine.solve().unwrap().0, &before);
}

#[test]
fn live_tier_finds_the_rigid_correspondence() {
    for objects in [16, 40] {
        let scene = RigidScene::new(objects, 5).unwrap();
        let exact = fresh(&scene.human, &scene.robot, Method::Paper);
        let mut engine = Engine::new(Method::Paper, Tier::Live, Params::default()).unwrap();
        engine.update(Side::Human, &scene.human).unwrap();
        engine.update(Side::Robot, &scene.robot).unwrap();
        let live = engine.solve().unwrap().0.clone();
        assert_eq!(live.assignment, exact.assignment, "{objects} objects");
        assert!(live.iterations <= exact.iterations);
        // Warm start after a move: the answer for the other objects holds.
        let moved = scene.moved(0, 3).unwrap();
        engine.update(Side::Human, &moved.human).unwrap();
        let (after, _, _) = engine.solve().unwrap();
        let same = after
            .assignment
            .iter()
            .zip(&live.assignment)
            .filter(|(a, b)| a == b)
            .count();
        assert!(same >= objects - 2, "{same} of {objects} kept");
    }
}

fn rigid_live(params: Params, human: &SceneGraph, robot: &SceneGraph) -> Engine {
    let mut engine = Engine::new(Method::Rigid, Tier::Live, params).unwrap();
    engine.update(Side::Human, human).unwrap();
    engine.update(Side::Robot, robot).unwrap();
    engine
}

#[test]
fn live_rigid_resumes_from_the_last_motions_while_they_explain_the_scene() {
    // 2 cm noise: no motion settles the scene, so a full search runs whole.
    let scene = RigidScene::with_noise(32, 9, 0.02).unwrap();
    let mut engine = rigid_live(Params::default(), &scene.human, &scene.robot);
    let first = engine.solve().unwrap().0.clone();
    assert!(!engine.resumed(), "the first solve searches");
    let exact = fresh(&scene.human, &scene.robot, Method::Rigid);
    assert_eq!(first, exact, "a full live solve is the exact tier's");

    let moved = scene.moved(0, 3).unwrap();
    engine.update(Side::Human, &moved.human).unwrap();
    let after = engine.solve().unwrap().0.clone();
    assert!(
        engine.resumed(),
        "one object moved: the last motions still fit"
    );
    let full = fresh(&moved.human, &moved.robot, Method::Rigid);
    let same = after
        .assignment
        .iter()
        .zip(&full.assignment)
        .filter(|(a, b)| a == b)
        .count();
    assert!(same >= 30, "{same} of 32 answers as a full search gives");

    // Another scene's human view: the last motions explain little of it,
    // so the solve searches afresh and answers as the exact tier.
    let other = RigidScene::with_noise(32, 77, 0.02).unwrap();
    engine.update(Side::Human, &other.human).unwrap();
    let got = engine.solve().unwrap().0.clone();
    assert!(!engine.resumed(), "an unrelated view is searched");
    assert_eq!(got, fresh(&other.human, &scene.robot, Method::Rigid));
}

/// Seven solves of `scene` by `engine`, one object moved before each:
/// whether each resumed. With `settle` a search apart is waited for after
/// each solve, so that it ends before the next whatever the machine's
/// speed: the same answers every run.
fn seven_moves(engine: &mut Engine, scene: &RigidScene, settle: bool) -> Vec<bool> {
    let mut resumed = Vec::new();
    for step in 0..7 {
        let moved = scene.moved(step, 11 + step as u64).unwrap();
        engine.update(Side::Human, &moved.human).unwrap();
        engine.solve().unwrap();
        resumed.push(engine.resumed());
        if settle {
            engine.settle();
        }
    }
    resumed
}

#[test]
fn live_rigid_searches_in_full_once_every_rigid_full_every_solves() {
    let scene = RigidScene::with_noise(16, 4, 0.02).unwrap();
    let mut params = Params::default();
    params.live.rigid_full_every = 3;
    params.live.rigid_full_apart = false;
    let mut engine = rigid_live(params, &scene.human, &scene.robot);
    let resumed = seven_moves(&mut engine, &scene, true);
    let searches = engine.full_searches();
    assert_eq!(
        resumed,
        [false, true, true, false, true, true, false],
        "full, then two resumed, in turn"
    );
    assert_eq!(searches, 3);

    params.live.rigid_full_every = 1;
    let mut engine = rigid_live(params, &scene.human, &scene.robot);
    for step in 0..3 {
        let moved = scene.moved(step, 5).unwrap();
        engine.update(Side::Human, &moved.human).unwrap();
        engine.solve().unwrap();
        assert!(!engine.resumed(), "1: every solve is a full search");
    }
}

#[test]
fn live_rigid_runs_the_due_full_search_apart_while_solves_resume() {
    let scene = RigidScene::with_noise(16, 4, 0.02).unwrap();
    let mut params = Params::default();
    params.live.rigid_full_every = 3;
    assert!(params.live.rigid_full_apart, "the default");
    let mut engine = rigid_live(params, &scene.human, &scene.robot);
    let resumed = seven_moves(&mut engine, &scene, true);
    let searches = engine.full_searches();
    assert_eq!(
        resumed,
        [false, true, true, true, true, true, true],
        "only the first solve searches on its own thread"
    );
    assert_eq!(
        searches, 3,
        "the first, then the two that fell due, taken up"
    );
}

/// An engine on `scene` (`rigid_full_every` 2) whose due full search has
/// just started apart: a full search, then two solves with one object
/// moved, both resumed.
fn search_apart_started(scene: &RigidScene) -> Engine {
    let mut params = Params::default();
    params.live.rigid_full_every = 2;
    let mut engine = rigid_live(params, &scene.human, &scene.robot);
    engine.solve().unwrap();
    for step in 0..2 {
        let moved = scene.moved(step, 3).unwrap();
        engine.update(Side::Human, &moved.human).unwrap();
        engine.solve().unwrap();
        assert!(engine.resumed(), "the due search runs apart");
    }
    engine
}

#[test]
fn a_search_apart_overtaken_by_a_changed_scene_is_left_behind() {
    // 64 objects at 2 cm: the search apart takes several times a resumed
    // solve, so it is still running when the changed scene is solved (on
    // a machine where it is not, this test passes without testing that).
    let mut engine = search_apart_started(&RigidScene::with_noise(64, 9, 0.02).unwrap());

    // Another scene's human view, nothing in common with the robot's: the
    // solve searches on its own thread, and the search apart (of the
    // scene before) must not replace what it found.
    let other = RigidScene::with_noise(64, 77, 0.02).unwrap();
    engine.update(Side::Human, &other.human).unwrap();
    let got = engine.solve().unwrap().0.clone();
    assert!(!engine.resumed(), "a changed scene is searched at once");
    let searches = engine.full_searches();
    engine.settle();
    assert_eq!(
        engine.full_searches(),
        searches,
        "the search apart, of the scene before, is left behind"
    );
    assert_eq!(engine.solution(), Some(&got));
}

#[test]
fn a_view_swapped_for_another_scene_is_searched_though_the_old_motions_fit() {
    let scene = RigidScene::with_noise(16, 4, 0.02).unwrap();
    let mut engine = rigid_live(Params::default(), &scene.human, &scene.robot);
    engine.solve().unwrap();
    // Same positions, new track ids (as a dataset's next scene or a
    // restarted feed gives): the kept motions fit the new robot view
    // perfectly, but they were found in a scene it is not part of.
    let raised = |graph: &SceneGraph| graph.with_ids_raised(1000, &Limits::default()).unwrap();
    let robot = raised(&scene.robot);
    engine.update(Side::Robot, &robot).unwrap();
    engine.solve().unwrap();
    assert!(!engine.resumed(), "a new robot view is searched");
    // Then the human view swaps too: what was found in the half-swapped
    // views does not carry over either.
    let human = raised(&scene.human);
    engine.update(Side::Human, &human).unwrap();
    let got = engine.solve().unwrap().0.clone();
    assert!(!engine.resumed(), "a new human view is searched");
    assert_eq!(got, fresh(&human, &robot, Method::Rigid));
    // Views that keep their objects resume again.
    let moved = scene.moved(0, 3).unwrap();
    engine.update(Side::Human, &raised(&moved.human)).unwrap();
    engine.solve().unwrap();
    assert!(engine.resumed(), "the same scene, one object moved");
}

/// The time a search apart may take to end, before a test fails instead
/// of waiting on.
const SEARCH_WITHIN: std::time::Duration = std::time::Duration::from_secs(60);

#[test]
fn an_ended_search_apart_asks_for_a_solve_though_no_view_changed() {
    let mut engine = search_apart_started(&RigidScene::with_noise(16, 4, 0.02).unwrap());
    // Neither view changes again: a scene held still must still get what
    // the search apart found.
    let started = std::time::Instant::now();
    while !engine.is_dirty() {
        assert!(
            started.elapsed() < SEARCH_WITHIN,
            "the ended search never asked for a solve"
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    engine.solve().unwrap();
    assert_eq!(engine.full_searches(), 2, "its motions were taken up");
    assert!(!engine.is_dirty(), "and nothing more is new");
}

/// Runs first on a search apart's thread: a search as slow as one
/// starved by a busy machine.
fn starve() {
    std::thread::sleep(std::time::Duration::from_secs(3));
}

#[test]
fn a_search_apart_long_overdue_gives_way_to_one_on_the_solve_thread() {
    let scene = RigidScene::with_noise(16, 4, 0.02).unwrap();
    let mut params = Params::default();
    params.live.rigid_full_every = 3;
    let mut engine = rigid_live(params, &scene.human, &scene.robot);
    engine.on_search_thread(starve);
    let resumed = seven_moves(&mut engine, &scene, false);
    // Seven quick solves take far less than the starved search's 3 s (on
    // a machine where they do not, the search apart is taken up instead
    // and this fails).
    assert_eq!(
        resumed,
        [false, true, true, true, true, true, false],
        "the search apart falls due at the fourth solve; two periods of three solves after the first search it gives way"
    );
    engine.settle();
    assert_eq!(
        engine.full_searches(),
        2,
        "the starved search, overtaken, is left behind"
    );
}
