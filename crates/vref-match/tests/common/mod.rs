//! Scene builders shared by the matching tests.
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)]

use nalgebra::{Rotation3, Vector3};
use proptest::prelude::*;
use vref_scene::{Limits, SceneGraph, SceneObject, ScenePair};

/// A scene as plain numbers, so proptest can shrink it.
#[derive(Debug, Clone)]
pub struct RawScene {
    pub positions: Vec<[f64; 3]>,
    pub features: Vec<Vec<f32>>,
}

/// `n` objects in a 1 m cube with distinct random 8-d features.
pub fn raw_scene(n: std::ops::RangeInclusive<usize>) -> impl Strategy<Value = RawScene> {
    n.prop_flat_map(|n| {
        (
            prop::collection::vec(prop::array::uniform3(0.0f64..1.0), n),
            prop::collection::vec(prop::collection::vec(0.0f32..1.0, 8), n),
        )
    })
    .prop_map(|(positions, features)| RawScene {
        positions,
        features,
    })
}

/// A random proper rotation (axis-angle) and translation.
pub fn rigid_motion() -> impl Strategy<Value = (Rotation3<f64>, Vector3<f64>)> {
    (
        prop::array::uniform3(-1.0f64..1.0),
        -3.1f64..3.1,
        prop::array::uniform3(-2.0f64..2.0),
    )
        .prop_map(|(axis, angle, t)| {
            let axis = Vector3::from(axis);
            let rot = if axis.norm() < 1e-3 {
                Rotation3::identity()
            } else {
                Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle)
            };
            (rot, Vector3::from(t))
        })
}

pub fn graph(objects: Vec<SceneObject>) -> SceneGraph {
    SceneGraph::new(objects, None, &Limits::default()).unwrap()
}

/// The human view holds the scene as given with ids 100.., the robot view
/// the same objects moved rigidly, with ids 500.. and listed in the order
/// `robot_order` (a permutation of the objects).
pub fn rigid_pair(
    raw: &RawScene,
    motion: &(Rotation3<f64>, Vector3<f64>),
    robot_order: &[usize],
    with_features: bool,
) -> ScenePair {
    let feature = |k: usize| {
        if with_features {
            raw.features[k].clone()
        } else {
            Vec::new()
        }
    };
    let human = raw
        .positions
        .iter()
        .enumerate()
        .map(|(k, p)| SceneObject::new(100 + k as u64, *p, feature(k)))
        .collect();
    let robot = robot_order
        .iter()
        .map(|&k| {
            let p = motion.0 * Vector3::from(raw.positions[k]) + motion.1;
            SceneObject::new(500 + k as u64, [p.x, p.y, p.z], feature(k))
        })
        .collect();
    let truth = (0..raw.positions.len())
        .map(|k| (100 + k as u64, 500 + k as u64))
        .collect();
    ScenePair::new("rigid".to_owned(), graph(robot), graph(human), truth).unwrap()
}

/// A permutation of 0..n from a proptest seed.
pub fn permutation(n: usize, seed: u64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n).collect();
    let mut state = seed | 1;
    for i in (1..n).rev() {
        // xorshift: enough to scramble a small vector reproducibly.
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        order.swap(i, (state % (i as u64 + 1)) as usize);
    }
    order
}
