//! A dataset scene's ground truth in a problem's row and column indices,
//! and the true motion, for the diagnostic examples (`error_law`,
//! `rigid_misses`, `rigid_ceiling`).

use std::collections::HashMap;

use nalgebra::Point3;
use vref_match::{Problem, RigidMotion};
use vref_scene::ScenePair;

/// Each human object's true partner, as a robot column; `None` for none.
pub fn true_partners(pair: &ScenePair, problem: &Problem) -> Vec<Option<usize>> {
    let column: HashMap<u64, usize> = pair
        .robot
        .objects()
        .iter()
        .enumerate()
        .map(|(j, o)| (o.id, j))
        .collect();
    let truth: HashMap<u64, u64> = pair.ground_truth.iter().copied().collect();
    let partners: Vec<Option<usize>> = pair
        .human
        .objects()
        .iter()
        .map(|o| truth.get(&o.id).and_then(|r| column.get(r).copied()))
        .collect();
    debug_assert_eq!(partners.len(), problem.n);
    partners
}

/// The positions of the true pairs (human, robot), leaving out row
/// `without`'s.
pub fn true_pairs(
    problem: &Problem,
    partners: &[Option<usize>],
    without: Option<usize>,
) -> (Vec<Point3<f64>>, Vec<Point3<f64>>) {
    partners
        .iter()
        .enumerate()
        .filter(|(i, _)| Some(*i) != without)
        .filter_map(|(i, j)| j.map(|j| (problem.human_positions[i], problem.robot_positions[j])))
        .unzip()
}

/// The rigid fit to `from` -> `to`, equally weighted; `None` below three
/// pairs.
pub fn fit(from: &[Point3<f64>], to: &[Point3<f64>]) -> Option<RigidMotion> {
    if from.len() < 3 {
        return None;
    }
    RigidMotion::fit(from, to, &vec![1.0; from.len()])
}
