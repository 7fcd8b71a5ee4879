#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{RawScene, permutation, raw_scene, rigid_motion, rigid_pair};
use proptest::prelude::*;
use vref_match::{MatchError, Method, Params, Problem, score_scene, solve};
use vref_scene::ScenePair;

fn params() -> Params {
    let mut params = Params {
        beta: 0.01,
        ..Params::default()
    };
    // The motions here move coordinates arbitrarily; they are not camera
    // poses, so `rigid`'s assumption that both cameras look at the objects
    // from the same side of their plane does not hold.
    params.rigid.same_side = false;
    params
}

fn id_pairs(method: Method, pair: &ScenePair) -> Vec<(u64, u64)> {
    let problem = Problem::new(&pair.human, &pair.robot, params().beta).unwrap();
    let mut pairs = solve(method, &problem, &params())
        .unwrap()
        .id_pairs(&pair.human, &pair.robot);
    pairs.sort_unstable();
    pairs
}

/// The same scene with the human objects listed in another order.
fn reorder_human(pair: &ScenePair, order: &[usize]) -> ScenePair {
    let objects = order
        .iter()
        .map(|&k| pair.human.objects()[k].clone())
        .collect();
    ScenePair::new(
        pair.name.clone(),
        pair.robot.clone(),
        common::graph(objects),
        pair.ground_truth.clone(),
    )
    .unwrap()
}

/// Drops the robot objects listed in `drop` (and their ground truth).
fn without_robot(pair: &ScenePair, keep: usize) -> ScenePair {
    let objects: Vec<_> = pair.robot.objects()[..keep].to_vec();
    let ids: Vec<u64> = objects.iter().map(|o| o.id).collect();
    let truth = pair
        .ground_truth
        .iter()
        .copied()
        .filter(|(_, r)| ids.contains(r))
        .collect();
    ScenePair::new(
        pair.name.clone(),
        common::graph(objects),
        pair.human.clone(),
        truth,
    )
    .unwrap()
}

/// The largest disagreement between the human and the robot distance of
/// any two of `pairs` (human id, robot id).
fn worst_disagreement(pair: &ScenePair, pairs: &[(u64, u64)]) -> f64 {
    let at = |graph: &vref_scene::SceneGraph, id: u64| {
        graph
            .objects()
            .iter()
            .find(|o| o.id == id)
            .unwrap()
            .position
    };
    let mut worst: f64 = 0.0;
    for (a, &(h1, r1)) in pairs.iter().enumerate() {
        for &(h2, r2) in &pairs[a + 1..] {
            let human = (at(&pair.human, h1) - at(&pair.human, h2)).norm();
            let robot = (at(&pair.robot, r1) - at(&pair.robot, r2)).norm();
            worst = worst.max((human - robot).abs());
        }
    }
    worst
}

fn scene() -> impl Strategy<Value = (RawScene, u64, u64)> {
    (raw_scene(4..=12), any::<u64>(), any::<u64>())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn noiseless_rigid_motion_is_matched_perfectly((raw, s1, _) in scene(), motion in rigid_motion()) {
        let pair = rigid_pair(&raw, &motion, &permutation(raw.positions.len(), s1), true);
        let ids: Vec<u64> = pair.human.objects().iter().map(|o| o.id).collect();
        for method in Method::ALL {
            let answer = id_pairs(method, &pair);
            let score = score_scene(&ids, &answer, &pair.ground_truth);
            if method == Method::Rigid {
                // `rigid` may abstain where a wrong motion fits nearly as
                // well as the right one at its residual scale (a scene of
                // four objects can allow that; none of 12 000 random scenes
                // did with the defaults, 4 with abstention at a looser
                // dispute threshold), but it never gives a wrong partner,
                // and without abstention it gets every object right.
                prop_assert_eq!(score.precision, 1.0, "{} on {:?}", method, raw);
                let mut sure = params();
                sure.rigid.abstain_share = 0.0;
                sure.rigid.abstain_share_evident = 0.0;
                let problem = Problem::new(&pair.human, &pair.robot, sure.beta).unwrap();
                let pairs = solve(method, &problem, &sure).unwrap().id_pairs(&pair.human, &pair.robot);
                let score = score_scene(&ids, &pairs, &pair.ground_truth);
                prop_assert_eq!(score.accuracy, 1.0, "{} without abstention on {:?}", method, raw);
            } else if method == Method::Clipper && score.accuracy < 1.0 {
                // `clipper` weighs distances alone, and its ascent is local:
                // where another labelling of a few objects keeps every
                // distance within its tolerance, it can settle on that
                // cluster (the regression file holds a scene of five where
                // it does). What it gives is still a consistent cluster.
                let tolerance = params().clipper.epsilon * (params().beta / 2.0).sqrt();
                let worst = worst_disagreement(&pair, &answer);
                prop_assert!(worst <= tolerance, "clipper on {:?}: distances disagree by {}", raw, worst);
            } else {
                prop_assert_eq!(score.accuracy, 1.0, "{} on {:?}", method, raw);
            }
        }
    }

    #[test]
    fn relabelling_either_graph_relabels_the_answer((raw, s1, s2) in scene(), motion in rigid_motion()) {
        let n = raw.positions.len();
        let pair = rigid_pair(&raw, &motion, &(0..n).collect::<Vec<_>>(), true);
        let robot_relabelled = rigid_pair(&raw, &motion, &permutation(n, s1), true);
        let human_relabelled = reorder_human(&pair, &permutation(n, s2));
        for method in Method::ALL {
            let base = id_pairs(method, &pair);
            prop_assert_eq!(&id_pairs(method, &robot_relabelled), &base, "{} robot order", method);
            prop_assert_eq!(&id_pairs(method, &human_relabelled), &base, "{} human order", method);
        }
    }

    #[test]
    fn every_result_is_one_to_one((raw, s1, _) in scene(), motion in rigid_motion(), keep in 1usize..=12) {
        let n = raw.positions.len();
        let full = rigid_pair(&raw, &motion, &permutation(n, s1), false);
        let pair = without_robot(&full, keep.min(n));
        for method in Method::ALL {
            let pairs = id_pairs(method, &pair);
            let most = pair.human.len().min(pair.robot.len());
            if matches!(method, Method::Rigid | Method::Clipper) {
                // `rigid` and `clipper` may leave objects without a partner.
                prop_assert!(pairs.len() <= most);
            } else {
                prop_assert_eq!(pairs.len(), most);
            }
            let mut humans: Vec<u64> = pairs.iter().map(|p| p.0).collect();
            let mut robots: Vec<u64> = pairs.iter().map(|p| p.1).collect();
            humans.dedup();
            robots.sort_unstable();
            robots.dedup();
            prop_assert_eq!(humans.len(), pairs.len());
            prop_assert_eq!(robots.len(), pairs.len());
        }
    }
}

#[test]
fn method_names_round_trip_and_unknown_names_are_refused() {
    for method in Method::ALL {
        assert_eq!(method.name().parse::<Method>().unwrap(), method);
    }
    assert_eq!(
        "rwm".parse::<Method>(),
        Err(MatchError::UnknownMethod("rwm".to_owned()))
    );
}

#[test]
fn bad_parameters_are_refused_by_name() {
    type Spoil = fn(&mut Params);
    let cases: [(&str, Spoil); 8] = [
        ("beta", |p| p.beta = 0.0),
        ("beta", |p| p.beta = f64::NAN),
        ("rrwm.c", |p| p.rrwm.c = 1.5),
        ("paper.alpha", |p| p.paper.alpha = -0.1),
        ("rrwm.amplification", |p| p.rrwm.amplification = 1000.0),
        ("sm.max_iter", |p| p.sm.max_iter = 0),
        ("rigid.abstain_share_evident", |p| {
            p.rigid.abstain_share_evident = 1.5
        }),
        ("rigid.abstain_evidence", |p| {
            p.rigid.abstain_evidence = f64::NAN
        }),
    ];
    for (name, spoil) in cases {
        let mut p = Params::default();
        spoil(&mut p);
        match p.validate() {
            Err(MatchError::BadParameter { name: got, .. }) => assert_eq!(got, name),
            other => panic!("{name}: {other:?}"),
        }
    }
    assert!(Params::default().validate().is_ok());
    let mut never = Params::default();
    never.rigid.abstain_evidence = f64::INFINITY;
    assert!(
        never.validate().is_ok(),
        "an infinite abstain_evidence means never"
    );
}

#[test]
fn empty_graph_is_refused() {
    let objects = vec![vref_scene::SceneObject::new(1, [0.0; 3], vec![])];
    let one = common::graph(objects);
    let empty = vref_scene::SceneGraph::new(
        vec![],
        None,
        &vref_scene::Limits {
            require_objects: false,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(
        Problem::new(&empty, &one, 1.0).unwrap_err(),
        MatchError::EmptyGraph { side: "human" }
    );
    assert_eq!(
        Problem::new(&one, &empty, 1.0).unwrap_err(),
        MatchError::EmptyGraph { side: "robot" }
    );
}

#[test]
fn iterative_methods_report_convergence_on_a_clean_scene() {
    let raw = RawScene {
        positions: vec![
            [0.0, 0.0, 0.0],
            [0.3, 0.0, 0.1],
            [0.0, 0.5, 0.2],
            [0.4, 0.4, 0.0],
            [0.1, 0.7, 0.6],
        ],
        features: (0..5)
            .map(|k| {
                (0..8)
                    .map(|d| ((k * 8 + d) as f32 * 0.7).sin().abs())
                    .collect()
            })
            .collect(),
    };
    let motion = (
        nalgebra::Rotation3::from_euler_angles(0.1, 0.2, 0.3),
        nalgebra::Vector3::new(0.5, 0.0, 1.0),
    );
    let pair = rigid_pair(&raw, &motion, &[3, 1, 4, 0, 2], true);
    let problem = Problem::new(&pair.human, &pair.robot, 0.01).unwrap();
    for method in [Method::Sm, Method::Rrwm, Method::Paper] {
        let s = solve(method, &problem, &params()).unwrap();
        assert!(s.converged, "{method} ran {} iterations", s.iterations);
        assert!(s.iterations >= 2);
        assert!(s.soft.iter().all(|v| v.is_finite()));
    }
}
