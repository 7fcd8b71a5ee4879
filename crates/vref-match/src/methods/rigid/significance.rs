//! How many pairs the best motion explains against how many a motion
//! explains by chance among this many candidates: an a-contrario test in
//! the manner of ORSA (Moisan and Stival 2004; Moisan, Moulon and Monasse
//! 2012), with the chance rate measured on the scene itself.
//!
//! The null model. Under a motion that has nothing to do with the scene, a
//! human object lands at a place unrelated to its partner's, and what it
//! pairs with there is chance. The chance that one object's best pair
//! under the motion costs at most `c` is measured, for this scene, this
//! motion and these noise scales, by moving the scene's human view with
//! its places shuffled in its plane ([`super::coincidence::null_view`]:
//! the same objects, appearance, footprint and spacing) and taking every
//! row's cheapest pair there: `p(c)` is the share of those rows at most
//! `c`. It holds the number of candidates (every robot object a row may
//! pair with, weighed by appearance), the gate (the cost of "no
//! partner", the noise scales) and the scene's extent, so nothing of them
//! is assumed.
//!
//! The test. The best motion's pairs, cheapest first, with `c_k` the
//! `k`-th cost: were they chance, `k` of the `n` rows would reach `c_k`
//! with probability at most `C(n, k) p(c_k)^(k - 3)` for the `C(k, 3)`
//! samples of three pairs that fix a motion exactly; the number of false
//! alarms over the `n - 3` values of `k` is
//! `NFA = min_k (n - 3) C(n, k) C(k, 3) p(c_k)^(k - 3)`, the expected
//! number of motions that chance alone makes look at least this good.
//! [`log10_nfa`] returns its logarithm; `rigid` reports `-log10 NFA` as
//! the motion's significance.

/// Base-10 logarithm of the number of false alarms of a motion whose
/// pairs cost `inliers` (any order), in a view of `rows` human objects,
/// against the chance costs `chance` (sorted ascending; one per row of
/// each shuffled view). `None` below four pairs or without chance costs:
/// three pairs fit any motion and prove nothing.
pub(super) fn log10_nfa(inliers: &[f64], rows: usize, chance: &[f64]) -> Option<f64> {
    if inliers.len() < 4 || chance.is_empty() || rows < inliers.len() {
        return None;
    }
    let mut costs = inliers.to_vec();
    costs.sort_by(f64::total_cmp);
    let samples = chance.len() as f64;
    let tests = ((rows - 3) as f64).ln();
    let mut best = f64::INFINITY;
    for k in 4..=costs.len() {
        let c = costs[k - 1];
        // Chance rows at most as cheap, plus one (no chance rate is
        // measured as zero from finitely many rows).
        let hits = chance.partition_point(|&x| x <= c) as f64;
        let p = ((hits + 1.0) / (samples + 1.0)).min(1.0);
        let ln_nfa = tests + ln_choose(rows, k) + ln_choose(k, 3) + (k - 3) as f64 * p.ln();
        best = best.min(ln_nfa);
    }
    best.is_finite().then(|| best / std::f64::consts::LN_10)
}

/// `ln C(n, k)`, exact in floating point for the sizes of a view.
fn ln_choose(n: usize, k: usize) -> f64 {
    if k > n {
        return f64::NEG_INFINITY;
    }
    let k = k.min(n - k);
    (1..=k).map(|t| ((n - k + t) as f64 / t as f64).ln()).sum()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::{ln_choose, log10_nfa};

    #[test]
    fn binomial_coefficients() {
        assert!((ln_choose(10, 3) - 120f64.ln()).abs() < 1e-12);
        assert!((ln_choose(256, 0)).abs() < 1e-12);
        assert!((ln_choose(7, 7)).abs() < 1e-12);
        assert_eq!(ln_choose(3, 4), f64::NEG_INFINITY);
    }

    /// A hand-computed case: 8 rows, four pairs of cost 1, chance costs of
    /// which 9 of 99 are at most 1: p = 10 / 100.
    #[test]
    fn a_hand_computed_number_of_false_alarms() {
        let mut chance = vec![0.5; 9];
        chance.extend(vec![3.0; 90]);
        let got = log10_nfa(&[1.0; 4], 8, &chance).unwrap();
        let expected = (5.0 * 70.0 * 4.0 * 0.1f64).log10();
        assert!((got - expected).abs() < 1e-9, "{got} against {expected}");
    }

    /// More pairs, cheaper pairs and rarer chance make a motion less of a
    /// coincidence; three pairs prove nothing.
    #[test]
    fn more_and_cheaper_pairs_are_less_of_a_coincidence() {
        let chance: Vec<f64> = (0..400).map(|k| f64::from(k) / 100.0).collect();
        let five = log10_nfa(&[0.5; 5], 10, &chance).unwrap();
        let eight = log10_nfa(&[0.5; 8], 10, &chance).unwrap();
        let loose = log10_nfa(&[2.0; 8], 10, &chance).unwrap();
        assert!(eight < five && eight < loose, "{five} {eight} {loose}");
        assert_eq!(log10_nfa(&[0.5; 3], 10, &chance), None);
        assert_eq!(log10_nfa(&[0.5; 5], 10, &[]), None);
    }
}
