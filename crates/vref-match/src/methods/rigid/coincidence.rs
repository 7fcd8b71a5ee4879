//! Whether the best motion explains the scene or only a few pairs by
//! chance. Among many candidates some motion always pairs a few objects
//! well; what tells a real motion is how far its score stands above the
//! scores that motions drawn at random reach in this scene, after the same
//! local optimisation (an a-contrario test in the manner of Moisan and
//! Stival's ORSA). The null is measured in the scene itself, from the
//! sampler's own hypotheses, most of which are wrong, so it holds on a
//! table of look-alikes as among random clouds; and the best of `tests`
//! chance draws is expected `sqrt(2 ln tests)` deviations above their
//! mean, which the margin is counted from.

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

/// The probability that a motion with `margin` is real: a logistic of the
/// margin with `slope`, even odds at `at`.
pub(super) fn real(margin: Option<f64>, slope: f64, at: f64) -> f64 {
    margin.map_or(1.0, |z| 1.0 / (1.0 + (-slope * (z - at)).exp()))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::{margin, real};

    /// A hand-computed margin: mean 10, spread 2 (sample), 100 tests.
    #[test]
    fn the_margin_of_a_hand_computed_case() {
        let chance = [8.0, 12.0, 8.0, 12.0, 10.0, 10.0];
        let spread = (16.0f64 / 5.0).sqrt();
        let expected = (20.0 - 10.0) / spread - (2.0 * 100f64.ln()).sqrt();
        assert!((margin(&chance, 20.0, 100).unwrap() - expected).abs() < 1e-12);
        assert_eq!(margin(&[3.0], 20.0, 100), None);
    }

    /// A motion scoring what chance scores is not real; one far above is,
    /// and more tests demand more.
    #[test]
    fn a_motion_is_real_only_beyond_what_chance_explains() {
        let chance = [5.0, 7.0, 6.0, 4.0, 8.0, 6.0, 5.0, 7.0];
        assert!(real(margin(&chance, 8.0, 400), 2.0, 0.5) < 0.05);
        assert!(real(margin(&chance, 30.0, 400), 2.0, 0.5) > 0.95);
        assert!(margin(&chance, 12.0, 40).unwrap() > margin(&chance, 12.0, 4000).unwrap());
        assert_eq!(real(None, 2.0, 0.5), 1.0);
    }
}
