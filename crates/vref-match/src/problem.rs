use vref_scene::SceneGraph;

use crate::{MatchError, SpatialAffinity, appearance_affinity};

/// Everything a method needs about two graphs: the appearance affinity
/// (row-major `n x m`) and the spatial affinity S.
#[derive(Debug, Clone)]
pub struct Problem {
    pub n: usize,
    pub m: usize,
    pub appearance: Vec<f64>,
    pub spatial: SpatialAffinity,
}

impl Problem {
    /// Builds the affinities of human graph `human` (rows) against robot
    /// graph `robot` (columns) with spatial bandwidth `beta`.
    pub fn new(human: &SceneGraph, robot: &SceneGraph, beta: f64) -> Result<Self, MatchError> {
        if human.is_empty() {
            return Err(MatchError::EmptyGraph { side: "human" });
        }
        if robot.is_empty() {
            return Err(MatchError::EmptyGraph { side: "robot" });
        }
        if !(beta.is_finite() && beta > 0.0) {
            return Err(MatchError::BadParameter {
                name: "beta",
                value: beta,
                expected: "positive and finite",
            });
        }
        Ok(Self {
            n: human.len(),
            m: robot.len(),
            appearance: appearance_affinity(human, robot)?,
            spatial: SpatialAffinity::new(human, robot, beta),
        })
    }

    /// Number of candidate pairs, `n * m`.
    pub fn len(&self) -> usize {
        self.n * self.m
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
