use std::collections::HashSet;

use crate::{GraphError, PairError, SceneGraph, Side};

/// Two views of one workspace and, where known, which human-view object is
/// which robot-view object.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenePair {
    pub name: String,
    pub robot: SceneGraph,
    pub human: SceneGraph,
    /// (human id, robot id), one-to-one; human objects absent here have no
    /// partner in the robot view.
    pub ground_truth: Vec<(u64, u64)>,
}

impl ScenePair {
    /// Checks that both graphs can be compared and that the ground truth is
    /// a one-to-one relation between known objects.
    pub fn new(
        name: String,
        robot: SceneGraph,
        human: SceneGraph,
        ground_truth: Vec<(u64, u64)>,
    ) -> Result<Self, PairError> {
        let (dh, dr) = (human.feature_dim(), robot.feature_dim());
        if dh != dr && !human.is_empty() && !robot.is_empty() {
            return Err(PairError::FeatureDimsDiffer {
                human: dh,
                robot: dr,
            });
        }
        check_ground_truth(&ground_truth, &human, &robot)?;
        Ok(Self {
            name,
            robot,
            human,
            ground_truth,
        })
    }

    /// Wraps a graph defect with the side it was found on.
    pub fn graph_error(side: Side) -> impl Fn(GraphError) -> PairError {
        move |source| PairError::Graph { side, source }
    }
}

fn check_ground_truth(
    pairs: &[(u64, u64)],
    human: &SceneGraph,
    robot: &SceneGraph,
) -> Result<(), PairError> {
    let mut seen_human = HashSet::with_capacity(pairs.len());
    let mut seen_robot = HashSet::with_capacity(pairs.len());
    for (index, &(h, r)) in pairs.iter().enumerate() {
        for (side, id, graph, seen) in [
            (Side::Human, h, human, &mut seen_human),
            (Side::Robot, r, robot, &mut seen_robot),
        ] {
            if graph.index_of(id).is_none() {
                return Err(PairError::UnknownGroundTruthId { index, side, id });
            }
            if !seen.insert(id) {
                return Err(PairError::GroundTruthNotOneToOne { index, side, id });
            }
        }
    }
    Ok(())
}
