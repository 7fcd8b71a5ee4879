//! Whether the best motion explains the scene or only a few pairs by
//! chance. Among many candidates some motion always pairs a few objects
//! well; what tells a real motion is how far its score stands above the
//! scores that motions drawn by the same sampler reach, after the same
//! local optimisation, in a view of this scene that no motion explains (an
//! a-contrario test in the manner of Moisan and Stival's ORSA). That view
//! is the scene's own human view with its objects' places in their plane
//! shuffled ([`null_view`]): the same objects, appearance, footprint and
//! spacing, so the null holds on a table of look-alikes as among random
//! clouds. The best of `tests` chance draws is expected `sqrt(2 ln tests)`
//! deviations above their mean, which the margin is counted from.

use nalgebra::{Point3, Vector3};

use super::RigidParams;
use super::search::SplitMix;
use crate::Problem;

/// The significance counted for a motion of under four pairs, which has
/// none (three pairs fix any motion): as if chance explained it
/// ten thousand times over.
const UNMEASURED_SIGNIFICANCE: f64 = -4.0;

/// What the coincidence rule weighs of the best motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Measures {
    /// `-log10` of its false alarms (`significance.rs`); `None` for a
    /// motion of under four pairs.
    pub(super) significance: Option<f64>,
    /// Its score margin over sampled chance ([`margin`]); infinite in a
    /// settled scene.
    pub(super) margin: f64,
    /// The share of the smaller view it pairs.
    pub(super) share: f64,
    /// Its score (the greedy gain over "no partner") under the noise
    /// scales assumed before the scene's own were estimated, over the
    /// largest possible, every object of the smaller view explained at no
    /// cost.
    pub(super) fit: f64,
}

/// How strongly a motion stands against chance: its significance, plus
/// `evidence_margin` times its margin, `evidence_share` times its share
/// and `evidence_fit` times its fit ([`Measures`]). A weighted sum, since
/// on the training files each alone passes unrelated views that real
/// scenes with few objects or wide depth error resemble, and their sum
/// separates them better than any test alone or all together
/// (docs/method.md, "Coincidence").
pub(super) fn evidence(measures: &Measures, rp: &RigidParams) -> f64 {
    // Chance does not settle a scene, whatever the margin's weight (0 x
    // infinity would be no number).
    if measures.margin == f64::INFINITY {
        return f64::INFINITY;
    }
    measures.significance.unwrap_or(UNMEASURED_SIGNIFICANCE)
        + rp.evidence_margin * measures.margin
        + rp.evidence_share * measures.share
        + rp.evidence_fit * measures.fit
}

/// `problem` with the human objects' coordinates along the two main axes
/// of their cloud (the plane a table top or floor spans) shuffled across
/// objects, each axis on its own, and the third kept: no rigid motion
/// maps this view onto the robot's beyond chance. The shuffle follows the
/// objects' order by position, so relabelling a view changes nothing. Its
/// places alone: `rigid` reads no affinity of a null view.
pub(super) fn null_view(problem: &Problem, seed: u64) -> Problem {
    let points = &problem.human_positions;
    let mut places = points.clone();
    let k = points.len();
    if k < 2 {
        return problem.with_human_places(places);
    }
    let centroid = points.iter().fold(Vector3::zeros(), |c, p| c + p.coords) / k as f64;
    let cov = points.iter().fold(nalgebra::Matrix3::zeros(), |acc, p| {
        let d = p.coords - centroid;
        acc + d * d.transpose()
    });
    let eig = cov.symmetric_eigen();
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let basis: [Vector3<f64>; 3] = axes.map(|a| eig.eigenvectors.column(a).into_owned());
    let mut order: Vec<usize> = (0..k).collect();
    order.sort_by(|&a, &b| {
        let (p, q) = (&points[a], &points[b]);
        p.x.total_cmp(&q.x)
            .then(p.y.total_cmp(&q.y))
            .then(p.z.total_cmp(&q.z))
    });
    let coords: Vec<[f64; 3]> = order
        .iter()
        .map(|&i| basis.map(|e| e.dot(&(points[i].coords - centroid))))
        .collect();
    let mut rng = SplitMix(seed ^ 0x6e75_6c6c);
    let mut shuffled = coords.clone();
    for axis in 0..2 {
        let mut column: Vec<f64> = coords.iter().map(|c| c[axis]).collect();
        for at in (1..k).rev() {
            column.swap(at, rng.below(at + 1));
        }
        for (c, v) in shuffled.iter_mut().zip(column) {
            c[axis] = v;
        }
    }
    for (&i, c) in order.iter().zip(&shuffled) {
        let p = centroid + basis[0] * c[0] + basis[1] * c[1] + basis[2] * c[2];
        places[i] = Point3::from(p);
    }
    problem.with_human_places(places)
}

/// Smallest spread of the chance scores, in nats: a few dozen draws that
/// happen to agree must not make any score look significant.
const SPREAD_FLOOR: f64 = 1.0;

/// The margin of `best` over the chance scores: deviations above their
/// mean beyond what the best of `tests` chance draws reaches. `None`
/// without chance scores.
pub(super) fn margin(chance: &[f64], best: f64, tests: usize) -> Option<f64> {
    if chance.len() < 2 {
        return None;
    }
    let k = chance.len() as f64;
    let mean = chance.iter().sum::<f64>() / k;
    let spread = (chance.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / (k - 1.0))
        .sqrt()
        .max(SPREAD_FLOOR);
    let expected_best = (2.0 * (tests.max(2) as f64).ln()).sqrt();
    Some((best - mean) / spread - expected_best)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::{Measures, RigidParams, evidence, margin};

    /// A hand-computed margin: mean 10, spread 2 (sample), 100 tests.
    #[test]
    fn the_margin_of_a_hand_computed_case() {
        let chance = [8.0, 12.0, 8.0, 12.0, 10.0, 10.0];
        let spread = (16.0f64 / 5.0).sqrt();
        let expected = (20.0 - 10.0) / spread - (2.0 * 100f64.ln()).sqrt();
        assert!((margin(&chance, 20.0, 100).unwrap() - expected).abs() < 1e-12);
        assert_eq!(margin(&[3.0], 20.0, 100), None);
    }

    fn measures(significance: Option<f64>, margin: f64, share: f64, fit: f64) -> Measures {
        Measures {
            significance,
            margin,
            share,
            fit,
        }
    }

    /// The evidence is the weighted sum, an unmeasured significance counts
    /// -4, and a settled scene (infinite margin) is never taken as chance.
    #[test]
    fn the_evidence_of_hand_computed_cases() {
        let rp = RigidParams {
            evidence_margin: 4.0,
            evidence_share: 12.0,
            evidence_fit: 8.0,
            ..RigidParams::default()
        };
        let of = |s, m, sh, f| evidence(&measures(s, m, sh, f), &rp);
        assert!((of(Some(-1.5), 0.5, 0.75, 0.5) - (-1.5 + 2.0 + 9.0 + 4.0)).abs() < 1e-12);
        assert!((of(None, -1.0, 0.5, 0.25) - (-4.0 - 4.0 + 6.0 + 2.0)).abs() < 1e-12);
        assert_eq!(of(Some(-9.0), f64::INFINITY, 0.0, 0.0), f64::INFINITY);
        let unweighted = RigidParams {
            evidence_margin: 0.0,
            ..rp
        };
        let of = |s, m, sh, f| evidence(&measures(s, m, sh, f), &unweighted);
        assert_eq!(of(None, f64::INFINITY, 0.0, 0.0), f64::INFINITY);
        assert!((of(Some(-1.0), -3.0, 0.5, 0.5) - 9.0).abs() < 1e-12);
    }

    /// More tests demand more of the best.
    #[test]
    fn more_tests_demand_more() {
        let chance = [5.0, 7.0, 6.0, 4.0, 8.0, 6.0, 5.0, 7.0];
        assert!(margin(&chance, 12.0, 40).unwrap() > margin(&chance, 12.0, 4000).unwrap());
        assert!(margin(&chance, 30.0, 400).unwrap() > margin(&chance, 8.0, 400).unwrap());
    }
}
