//! Turning a method's raw confidence into a probability that the answer is
//! right, and measuring how well that works (expected calibration error).

use serde::{Deserialize, Serialize};

/// Bins of [`expected_calibration_error`]'s default use (`vref eval`).
pub const ECE_BINS: usize = 10;

/// A logistic map `p = 1 / (1 + exp(-(bias + slope * logit(raw) + no_partner_shift * [no partner])))`
/// from a raw row share to a probability; answers "no partner" get their
/// own offset, since their share comes from a different part of the model.
/// The constants are fitted on training seeds by
/// `tools/fit-calibration.py` (see its header for the command).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Calibration {
    pub bias: f64,
    pub slope: f64,
    pub no_partner_shift: f64,
}

impl Default for Calibration {
    fn default() -> Self {
        // Fitted by `python3 tools/fit-calibration.py --seeds 100-109`
        // (moi and mrc, 30 scenes per seed, 5875 answers).
        Self {
            bias: 2.8974,
            slope: 0.5719,
            no_partner_shift: -1.4116,
        }
    }
}

/// Raw shares are clamped this far from 0 and 1 before the logit, so that
/// a share of exactly 1 does not become an infinite certainty.
const SHARE_EPS: f64 = 1e-6;

impl Calibration {
    /// The probability that an answer with row share `raw` (in [0, 1]) is
    /// right; `no_partner` when the answer is "no partner".
    pub fn probability(&self, raw: f64, no_partner: bool) -> f64 {
        let raw = if raw.is_finite() { raw } else { 0.0 };
        let shift = if no_partner {
            self.no_partner_shift
        } else {
            0.0
        };
        let z = self.bias + self.slope * logit(raw) + shift;
        1.0 / (1.0 + (-z).exp())
    }
}

/// `ln(p / (1 - p))` with `p` clamped into `[SHARE_EPS, 1 - SHARE_EPS]`.
pub fn logit(p: f64) -> f64 {
    let p = p.clamp(SHARE_EPS, 1.0 - SHARE_EPS);
    (p / (1.0 - p)).ln()
}

/// Expected calibration error of `(confidence, correct)` answers over
/// `bins` equal-width bins of confidence in [0, 1]: the sum over bins of
/// the bin's share of answers times `|mean confidence - accuracy|` in it.
/// Confidence 1 falls in the last bin. 0 for no answers or no bins.
pub fn expected_calibration_error(answers: &[(f64, bool)], bins: usize) -> f64 {
    if answers.is_empty() || bins == 0 {
        return 0.0;
    }
    let mut count = vec![0usize; bins];
    let mut confidence = vec![0.0; bins];
    let mut right = vec![0usize; bins];
    for &(c, ok) in answers {
        let c = if c.is_finite() {
            c.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let b = ((c * bins as f64) as usize).min(bins - 1);
        count[b] += 1;
        confidence[b] += c;
        right[b] += usize::from(ok);
    }
    let total = answers.len() as f64;
    (0..bins)
        .filter(|&b| count[b] > 0)
        .map(|b| {
            let k = count[b] as f64;
            (k / total) * (confidence[b] / k - right[b] as f64 / k).abs()
        })
        .sum()
}
