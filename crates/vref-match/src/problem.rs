use nalgebra::{Point3, Vector3};

use crate::RigidMotion;
use vref_scene::SceneGraph;

use crate::{
    MatchError, PairAffinity, Params, SpatialAffinity, SpatialTerm, appearance_affinity,
    candidate_pairs, distance_matrix,
};

/// Everything a method needs about two graphs: the appearance affinity
/// (row-major `n x m`) and the spatial affinity S.
#[derive(Debug, Clone)]
pub struct Problem {
    pub n: usize,
    pub m: usize,
    pub appearance: Vec<f64>,
    pub spatial: SpatialTerm,
    /// Positions of the human objects (rows), in the human camera frame.
    pub human_positions: Vec<Point3<f64>>,
    /// Positions of the robot objects (columns), in the robot camera frame.
    pub robot_positions: Vec<Point3<f64>>,
    /// Per human object, its position error per axis (standard
    /// deviations, its own camera frame) as its sensor states it; empty or
    /// zero when not stated.
    pub human_sigmas: Vec<[f64; 3]>,
    /// Likewise per robot object.
    pub robot_sigmas: Vec<[f64; 3]>,
    /// Which way is up in the human camera frame (unit), where known.
    pub human_up: Option<Vector3<f64>>,
    /// Which way is up in the robot camera frame (unit), where known.
    pub robot_up: Option<Vector3<f64>>,
}

/// The mean over the three axes of the squared stated position errors:
/// the variance per axis of an isotropic error with the same total, which
/// a rotation between the two camera frames leaves unchanged.
pub fn position_variance(sigma: &[f64; 3]) -> f64 {
    sigma.iter().map(|s| s * s).sum::<f64>() / 3.0
}

fn sigmas(graph: &SceneGraph) -> Vec<[f64; 3]> {
    graph.objects().iter().map(|o| o.position_sigma).collect()
}

impl Problem {
    /// Builds the affinities of human graph `human` (rows) against robot
    /// graph `robot` (columns) with spatial bandwidth `beta`: every pair
    /// (the exact tier).
    pub fn new(human: &SceneGraph, robot: &SceneGraph, beta: f64) -> Result<Self, MatchError> {
        check_graphs(human, robot)?;
        check_beta(beta)?;
        Ok(Self {
            n: human.len(),
            m: robot.len(),
            appearance: appearance_affinity(human, robot)?,
            spatial: SpatialTerm::Edges(SpatialAffinity::new(human, robot, beta)),
            human_positions: human.objects().iter().map(|o| o.position).collect(),
            robot_positions: robot.objects().iter().map(|o| o.position).collect(),
            human_sigmas: sigmas(human),
            robot_sigmas: sigmas(robot),
            human_up: human.up(),
            robot_up: robot.up(),
        })
    }

    /// The live tier's problem: only the candidate pairs of
    /// [`candidate_pairs`]; every other pair has appearance 0 and no
    /// spatial affinity, so methods leave it at zero.
    pub fn live(
        human: &SceneGraph,
        robot: &SceneGraph,
        params: &Params,
    ) -> Result<Self, MatchError> {
        check_graphs(human, robot)?;
        check_beta(params.beta)?;
        let (n, m) = (human.len(), robot.len());
        let appearance = appearance_affinity(human, robot)?;
        let pairs = candidate_pairs(&appearance, n, m, &params.live);
        let spatial = PairAffinity::new(
            n,
            m,
            pairs,
            &distance_matrix(human),
            &distance_matrix(robot),
            params.beta,
        );
        let mut problem = Self::pruned(n, m, appearance, spatial);
        problem.human_positions = human.objects().iter().map(|o| o.position).collect();
        problem.robot_positions = robot.objects().iter().map(|o| o.position).collect();
        problem.human_sigmas = sigmas(human);
        problem.robot_sigmas = sigmas(robot);
        problem.human_up = human.up();
        problem.robot_up = robot.up();
        Ok(problem)
    }

    /// This problem's places with the human objects at
    /// `human_positions`, and no affinities: a live-tier problem without
    /// candidate pairs, whose positions, stated errors and up vectors are
    /// this one's. What a method that reads only places asks of a made-up
    /// view (`rigid`'s null views, nine a solve), without copying the
    /// affinities (about a megabyte at 64 objects).
    pub(crate) fn with_human_places(&self, human_positions: Vec<Point3<f64>>) -> Self {
        let (n, m) = (self.n, self.m);
        Self {
            human_positions,
            robot_positions: self.robot_positions.clone(),
            human_sigmas: self.human_sigmas.clone(),
            robot_sigmas: self.robot_sigmas.clone(),
            human_up: self.human_up,
            robot_up: self.robot_up,
            ..Self::pruned(n, m, vec![0.0; n * m], PairAffinity::none(n, m))
        }
    }

    /// A live-tier problem from its parts: `appearance` is masked to the
    /// candidate pairs of `spatial`.
    pub fn pruned(n: usize, m: usize, mut appearance: Vec<f64>, spatial: PairAffinity) -> Self {
        let mut keep = vec![false; n * m];
        spatial.pairs().iter().for_each(|&f| keep[f] = true);
        appearance
            .iter_mut()
            .zip(&keep)
            .filter(|(_, kept)| !**kept)
            .for_each(|(a, _)| *a = 0.0);
        // Positions are the caller's to fill (`live`, the engine).
        Self {
            n,
            m,
            appearance,
            spatial: SpatialTerm::Pairs(spatial),
            human_positions: Vec::new(),
            robot_positions: Vec::new(),
            human_sigmas: Vec::new(),
            robot_sigmas: Vec::new(),
            human_up: None,
            robot_up: None,
        }
    }

    /// Per human object, the variance per axis of an isotropic error with
    /// the stated one's total ([`position_variance`]); empty when none is
    /// stated.
    pub fn human_variances(&self) -> Vec<f64> {
        self.human_sigmas.iter().map(position_variance).collect()
    }

    /// Likewise per robot object.
    pub fn robot_variances(&self) -> Vec<f64> {
        self.robot_sigmas.iter().map(position_variance).collect()
    }

    /// Both views' up vectors (human, robot), where both are known.
    pub fn gravity(&self) -> Option<(Vector3<f64>, Vector3<f64>)> {
        self.human_up.zip(self.robot_up)
    }

    /// The least-squares proper motion taking human positions `from` to
    /// robot positions `to`: with both up vectors known, one that takes
    /// the human up to the robot's ([`RigidMotion::fit_upright`]), else any
    /// ([`RigidMotion::fit`]).
    pub fn fit_motion(
        &self,
        from: &[Point3<f64>],
        to: &[Point3<f64>],
        weights: &[f64],
    ) -> Option<RigidMotion> {
        match self.gravity() {
            Some((h, r)) => RigidMotion::fit_upright(from, to, weights, &h, &r),
            None => RigidMotion::fit(from, to, weights),
        }
    }

    /// Number of candidate pairs, `n * m`.
    pub fn len(&self) -> usize {
        self.n * self.m
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

fn check_graphs(human: &SceneGraph, robot: &SceneGraph) -> Result<(), MatchError> {
    if human.is_empty() {
        return Err(MatchError::EmptyGraph { side: "human" });
    }
    if robot.is_empty() {
        return Err(MatchError::EmptyGraph { side: "robot" });
    }
    Ok(())
}

pub(crate) fn check_beta(beta: f64) -> Result<(), MatchError> {
    if beta.is_finite() && beta > 0.0 {
        Ok(())
    } else {
        Err(MatchError::BadParameter {
            name: "beta",
            value: beta,
            expected: "positive and finite",
        })
    }
}
