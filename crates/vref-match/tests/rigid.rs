#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! vref's own method: the rigid alignment under it, its handling of
//! objects without a partner, and the calibration measures.

use nalgebra::{Point3, Rotation3, Vector3};
use vref_match::{
    Calibration, Method, Params, Problem, RigidMotion, expected_calibration_error, logit, solve,
};
use vref_scene::{Limits, SceneGraph, SceneObject};

/// Ten points spread in all three dimensions (a mirror image of a nearly
/// flat cloud is nearly a rotation of it), none symmetric to another.
fn cloud() -> Vec<Point3<f64>> {
    [
        [0.00, 0.00, 0.00],
        [0.31, 0.02, 0.15],
        [0.12, 0.27, 0.03],
        [-0.18, 0.11, 0.27],
        [0.05, -0.22, 0.42],
        [0.26, -0.15, 0.06],
        [-0.09, -0.07, 0.63],
        [0.19, 0.18, 0.51],
        [-0.25, -0.19, 0.12],
        [0.08, 0.36, 0.33],
    ]
    .iter()
    .map(|p| Point3::new(p[0], p[1], p[2]))
    .collect()
}

fn known_motion() -> (Rotation3<f64>, Vector3<f64>) {
    (
        Rotation3::from_euler_angles(0.4, -1.1, 2.5),
        Vector3::new(0.7, -0.3, 1.9),
    )
}

#[test]
fn kabsch_recovers_a_known_rotation_and_translation() {
    let (rotation, translation) = known_motion();
    let from = cloud();
    let to: Vec<_> = from.iter().map(|p| rotation * p + translation).collect();
    let fit = RigidMotion::fit(&from, &to, &vec![1.0; from.len()]).unwrap();
    assert!((fit.rotation - rotation.matrix()).abs().max() < 1e-9);
    assert!((fit.translation - translation).abs().max() < 1e-9);
    assert!(fit.rms(&from, &to) < 1e-9);
}

#[test]
fn kabsch_weights_ignore_a_pair_of_weight_zero() {
    let (rotation, translation) = known_motion();
    let from = cloud();
    let mut to: Vec<_> = from.iter().map(|p| rotation * p + translation).collect();
    to[3] += Vector3::new(5.0, 0.0, 0.0);
    let mut weights = vec![1.0; from.len()];
    weights[3] = 0.0;
    let fit = RigidMotion::fit(&from, &to, &weights).unwrap();
    assert!((fit.translation - translation).abs().max() < 1e-9);
}

#[test]
fn a_mirror_image_is_not_fitted_by_a_reflection() {
    let (rotation, translation) = known_motion();
    let from = cloud();
    // Mirror through the x = 0 plane, then move rigidly.
    let to: Vec<_> = from
        .iter()
        .map(|p| rotation * Point3::new(-p.x, p.y, p.z) + translation)
        .collect();
    let fit = RigidMotion::fit(&from, &to, &vec![1.0; from.len()]).unwrap();
    assert!((fit.rotation.determinant() - 1.0).abs() < 1e-9);
    // The cloud is about 0.3 m across; a proper motion cannot explain its
    // mirror image to better than centimetres.
    assert!(fit.rms(&from, &to) > 0.03, "rms {}", fit.rms(&from, &to));
}

#[test]
fn degenerate_inputs_give_no_motion() {
    let p = cloud();
    assert!(RigidMotion::fit(&p, &p[..3], &[1.0; 3]).is_none());
    assert!(RigidMotion::fit(&p[..3], &p[..3], &[0.0; 3]).is_none());
    assert!(RigidMotion::fit(&[], &[], &[]).is_none());
}

fn graph(
    points: &[Point3<f64>],
    ids: impl Iterator<Item = u64>,
    features: &[Vec<f32>],
) -> SceneGraph {
    let objects = points
        .iter()
        .zip(ids)
        .zip(features)
        .map(|((p, id), f)| SceneObject::new(id, [p.x, p.y, p.z], f.clone()))
        .collect();
    SceneGraph::new(objects, None, &Limits::default()).unwrap()
}

/// Two look-alike kinds of object, so that appearance cannot decide.
fn features(n: usize) -> Vec<Vec<f32>> {
    (0..n)
        .map(|k| {
            if k % 2 == 0 {
                vec![1.0, 0.1]
            } else {
                vec![0.1, 1.0]
            }
        })
        .collect()
}

#[test]
fn an_object_the_robot_does_not_see_stays_unmatched() {
    let (rotation, translation) = known_motion();
    let mut human = cloud();
    // The human view has one more object, far from every robot object.
    human.push(Point3::new(0.9, 0.9, 0.5));
    let robot: Vec<_> = cloud().iter().map(|p| rotation * p + translation).collect();
    let human_graph = graph(&human, 1..=11, &features(11));
    let robot_graph = graph(&robot, 101..=110, &features(10));
    let params = Params::default();
    let problem = Problem::new(&human_graph, &robot_graph, params.beta).unwrap();

    let rigid = solve(Method::Rigid, &problem, &params).unwrap();
    for i in 0..10 {
        assert_eq!(rigid.assignment[i], Some(i), "row {i}");
    }
    assert_eq!(rigid.assignment[10], None);
    assert_eq!(rigid.confidence.len(), 11);
    assert!(rigid.confidence.iter().all(|c| (0.0..=1.0).contains(c)));

    // With more robot than human objects, the published methods give
    // every human object a partner, so the extra one takes someone's.
    let mut robot_more = robot.clone();
    robot_more.push(Point3::new(-2.0, 3.0, 1.0));
    let robot_graph = graph(&robot_more, 101..=111, &features(11));
    let problem = Problem::new(&human_graph, &robot_graph, params.beta).unwrap();
    let paper = solve(Method::Paper, &problem, &params).unwrap();
    assert!(paper.assignment.iter().all(Option::is_some));
    let rigid = solve(Method::Rigid, &problem, &params).unwrap();
    assert_eq!(rigid.assignment[10], None);
    assert!(rigid.assignment[..10].iter().all(Option::is_some));
}

#[test]
fn a_mirrored_robot_view_is_not_matched_as_if_rigid() {
    let (rotation, translation) = known_motion();
    let human = cloud();
    let mirrored: Vec<_> = human
        .iter()
        .map(|p| rotation * Point3::new(-p.x, p.y, p.z) + translation)
        .collect();
    let robot: Vec<_> = human.iter().map(|p| rotation * p + translation).collect();
    let g = features(10);
    let h = graph(&human, 1..=10, &g);
    let params = Params::default();
    let right = solve(
        Method::Rigid,
        &Problem::new(&h, &graph(&robot, 101..=110, &g), params.beta).unwrap(),
        &params,
    )
    .unwrap();
    let mirror = solve(
        Method::Rigid,
        &Problem::new(&h, &graph(&mirrored, 101..=110, &g), params.beta).unwrap(),
        &params,
    )
    .unwrap();
    let right_count = right.assignment.iter().filter(|a| a.is_some()).count();
    let mirror_right = mirror
        .assignment
        .iter()
        .enumerate()
        .filter(|(i, a)| **a == Some(*i))
        .count();
    assert_eq!(right_count, 10);
    // Distances alone cannot tell a scene from its mirror image; the
    // proper motion can: most of the mirror stays unexplained.
    assert!(
        mirror_right <= 5,
        "{mirror_right} of the mirror matched as-is"
    );
}

#[test]
fn ece_of_a_hand_computed_example() {
    // Bin [0.2, 0.3): confidences 0.2 and 0.25, one right: |0.225 - 0.5| = 0.275.
    // Bin [0.9, 1.0]: confidences 0.9, 1.0, 0.95, all right: |0.95 - 1| = 0.05.
    // ECE = 2/5 * 0.275 + 3/5 * 0.05 = 0.11 + 0.03 = 0.14.
    let answers = [
        (0.2, true),
        (0.25, false),
        (0.9, true),
        (1.0, true),
        (0.95, true),
    ];
    let ece = expected_calibration_error(&answers, 10);
    assert!((ece - 0.14).abs() < 1e-12, "{ece}");
    assert_eq!(expected_calibration_error(&[], 10), 0.0);
    // Perfectly calibrated: half right at confidence 0.5.
    let half = [(0.5, true), (0.5, false)];
    assert!(expected_calibration_error(&half, 10).abs() < 1e-12);
}

#[test]
fn the_calibration_map_is_a_logistic_of_the_share() {
    let identity = Calibration {
        bias: 0.0,
        slope: 1.0,
        no_partner_shift: 0.0,
    };
    for p in [0.1, 0.5, 0.73, 0.99] {
        assert!((identity.probability(p, false) - p).abs() < 1e-9);
    }
    let fitted = Calibration::default();
    // Monotone in the share; "no partner" shifted by its own offset.
    assert!(fitted.probability(0.9, false) > fitted.probability(0.6, false));
    let z = fitted.bias + fitted.slope * logit(0.6) + fitted.no_partner_shift;
    let expected = 1.0 / (1.0 + (-z).exp());
    assert!((fitted.probability(0.6, true) - expected).abs() < 1e-12);
    assert!(fitted.probability(f64::NAN, false).is_finite());
}
