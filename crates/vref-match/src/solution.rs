use vref_scene::SceneGraph;

use crate::RigidMotion;

/// What a method found.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// The method's soft correspondence, row-major `n x m`.
    pub soft: Vec<f64>,
    /// For each human object (row), the robot object (column) it is
    /// matched to, or `None` for no partner.
    pub assignment: Vec<Option<usize>>,
    /// For each row, the probability that its assignment (a partner, or
    /// none) is right: calibrated for `rigid`, the soft row share for the
    /// published methods (docs/method.md, "Choices where ALGORITHMS.md leaves
    /// room").
    pub confidence: Vec<f64>,
    /// Iterations of the method's main loop (0 for closed-form methods).
    pub iterations: usize,
    /// Whether the main loop met its tolerance before its iteration limit.
    pub converged: bool,
    /// The motion taking human-view positions to robot-view positions that
    /// the answer rests on, for methods that estimate one (`rigid`); `None`
    /// for the others, and when `rigid` found no motion.
    pub motion: Option<RigidMotion>,
    /// How far the motion stands above what chance explains, in deviations
    /// of the chance scores beyond the best chance reaches (`rigid`, when
    /// measured); `None` otherwise.
    pub margin: Option<f64>,
    /// `-log10` of the motion's number of false alarms against chance
    /// (`rigid`, for motions of at least four pairs); `None` otherwise.
    pub significance: Option<f64>,
    /// The motion's score (its greedy gain over "no partner") under the
    /// noise scales assumed before the scene's own were estimated, over
    /// the largest possible, every object of the smaller view explained at
    /// no cost (`rigid`, when it found a motion); `None` otherwise.
    pub fit: Option<f64>,
    /// Per row, its pair's squared Mahalanobis residual under `motion`
    /// against both objects' stated errors ([`crate::pair_residuals`]);
    /// empty for methods without a motion.
    pub residuals: Vec<Option<f64>>,
}

impl Solution {
    /// The verdict `rule` gives row `row`'s answer at `confidence` (the
    /// solution's own, or less where the row was only partly pointed at).
    pub fn verdict(&self, row: usize, confidence: f64, rule: &crate::OkRule) -> crate::Verdict {
        let partnered = self.assignment.get(row).copied().flatten().is_some();
        let residual = self.residuals.get(row).copied().flatten();
        rule.verdict(confidence, partnered, residual)
    }

    /// The matched pairs as (human track id, robot track id).
    pub fn id_pairs(&self, human: &SceneGraph, robot: &SceneGraph) -> Vec<(u64, u64)> {
        self.assignment
            .iter()
            .enumerate()
            .filter_map(|(i, a)| a.map(|a| (human.objects()[i].id, robot.objects()[a].id)))
            .collect()
    }
}
