#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! `clipper`: the densest consistent subgraph of candidate pairs.

use nalgebra::{Point3, Rotation3, Vector3};
use vref_match::{Method, Params, Problem, solve};
use vref_scene::{Limits, SceneGraph, SceneObject};

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
    ]
    .iter()
    .map(|p| Point3::new(p[0], p[1], p[2]))
    .collect()
}

fn graph(points: &[Point3<f64>], first_id: u64) -> SceneGraph {
    let objects = points
        .iter()
        .enumerate()
        .map(|(k, p)| SceneObject::new(first_id + k as u64, [p.x, p.y, p.z], Vec::new()))
        .collect();
    SceneGraph::new(objects, None, &Limits::default()).unwrap()
}

/// Objects one view alone sees fit no cluster of consistent pairs: they
/// are left without a partner, and the rest are matched.
#[test]
fn objects_one_view_alone_sees_stay_unmatched() {
    let rotation = Rotation3::from_euler_angles(0.3, -0.8, 1.9);
    let translation = Vector3::new(0.4, -0.2, 1.5);
    let mut human = cloud();
    human.push(Point3::new(0.9, 0.9, 0.5));
    human.push(Point3::new(-0.7, 0.8, -0.4));
    let robot: Vec<_> = cloud().iter().map(|p| rotation * p + translation).collect();
    let params = Params::default();
    let problem = Problem::new(&graph(&human, 1), &graph(&robot, 101), params.beta).unwrap();
    let solution = solve(Method::Clipper, &problem, &params).unwrap();
    for i in 0..8 {
        assert_eq!(solution.assignment[i], Some(i), "row {i}");
    }
    assert_eq!(solution.assignment[8], None);
    assert_eq!(solution.assignment[9], None);
    assert!(solution.converged);
    assert!(solution.confidence.iter().all(|c| (0.0..=1.0).contains(c)));
}

/// With a distance tolerance far below the views' disagreement, no two
/// pairs are consistent: at most one pair can be kept.
#[test]
fn views_that_keep_no_distance_give_at_most_one_pair() {
    let human = cloud();
    let robot: Vec<_> = cloud()
        .iter()
        .enumerate()
        .map(|(k, p)| Point3::new(p.x * (1.0 + 0.7 * k as f64), p.y * 3.0, -p.z))
        .collect();
    let params = Params {
        beta: 1e-8,
        ..Params::default()
    };
    let problem = Problem::new(&graph(&human, 1), &graph(&robot, 101), params.beta).unwrap();
    let solution = solve(Method::Clipper, &problem, &params).unwrap();
    assert!(solution.assignment.iter().flatten().count() <= 1);
}

/// Objects in pairs mirrored across a level plane keep every distance
/// under the mirrored pairing too: only the rise along up tells the two
/// pairings apart. With both up vectors `clipper` keeps the pairing whose
/// rises agree, and with the robot's up turned over, the mirror image.
#[test]
fn up_vectors_tell_a_layout_from_its_mirror_across_a_level_plane() {
    let lower = [
        [0.00, 0.00, -0.10],
        [0.31, 0.02, -0.15],
        [0.12, 0.27, -0.03],
        [-0.18, 0.11, -0.27],
    ];
    let mut human: Vec<_> = lower
        .iter()
        .map(|p| Point3::new(p[0], p[1], p[2]))
        .collect();
    human.extend(lower.iter().map(|p| Point3::new(p[0], p[1], -p[2])));
    let rotation = Rotation3::from_euler_angles(0.3, -0.8, 1.9);
    let translation = Vector3::new(0.4, -0.2, 1.5);
    let robot: Vec<_> = human.iter().map(|p| rotation * p + translation).collect();
    let up = Vector3::new(0.0, 0.0, 1.0);
    let robot_up = rotation * up;
    let mirror = |i: usize| (i + 4) % 8;
    let params = Params::default();
    for (sign, expected) in [
        (1.0, (0..8).collect::<Vec<_>>()),
        (-1.0, (0..8).map(mirror).collect()),
    ] {
        let human_graph = graph(&human, 1).with_up(Some([up.x, up.y, up.z])).unwrap();
        let turned = sign * robot_up;
        let robot_graph = graph(&robot, 101)
            .with_up(Some([turned.x, turned.y, turned.z]))
            .unwrap();
        let problem = Problem::new(&human_graph, &robot_graph, params.beta).unwrap();
        let solution = solve(Method::Clipper, &problem, &params).unwrap();
        let answer: Vec<_> = solution.assignment.iter().map(|a| a.unwrap()).collect();
        assert_eq!(answer, expected, "robot up x {sign}");
    }
}
