//! Turning a method's raw confidence into a probability that the answer is
//! right, and measuring how well that works (expected calibration error).

use serde::{Deserialize, Serialize};

/// Bins of [`expected_calibration_error`]'s default use (`vref eval`).
pub const ECE_BINS: usize = 10;

/// A logistic map `p = 1 / (1 + exp(-(bias + slope * logit(raw) +
/// no_partner_shift * [no partner] + margin term)))` from a raw row share
/// to a probability; answers "no partner" get their own offset, since
/// their share comes from a different part of the model. The margin term
/// is `partner_margin * g` for a partner and `none_margin * g` for "no
/// partner", `g` the best motion's margin over chance (clamped to
/// [-MARGIN_CAP, MARGIN_CAP]): a partner is only as sure as the motion it
/// rests on is unlike a coincidence.
/// The constants are fitted on training seeds by
/// `tools/fit-calibration.py` (see its header for the command).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Calibration {
    pub bias: f64,
    pub slope: f64,
    pub no_partner_shift: f64,
    pub partner_margin: f64,
    pub none_margin: f64,
}

/// Margins over chance beyond this tell nothing more.
pub const MARGIN_CAP: f64 = 3.0;

impl Default for Calibration {
    fn default() -> Self {
        // Fitted by `python3 tools/fit-calibration.py` on the training
        // files of every family (docs/method.md, "How each data set is
        // used": vref-sim seeds 100-109, the external sets' first halves,
        // the rendered scenes 000000-000005).
        Self {
            bias: 0.8088,
            slope: 0.9472,
            no_partner_shift: 1.7063,
            partner_margin: 0.4861,
            none_margin: 0.2213,
        }
    }
}

/// Raw shares are clamped this far from 0 and 1 before the logit, so that
/// a share of exactly 1 does not become an infinite certainty.
const SHARE_EPS: f64 = 1e-6;

impl Calibration {
    /// The probability that an answer with row share `raw` (in [0, 1]) is
    /// right; `no_partner` when the answer is "no partner"; `margin` the
    /// best motion's margin over chance (`MARGIN_CAP` when unmeasured).
    pub fn probability(&self, raw: f64, no_partner: bool, margin: f64) -> f64 {
        let raw = if raw.is_finite() { raw } else { 0.0 };
        let g = if margin.is_finite() {
            margin.clamp(-MARGIN_CAP, MARGIN_CAP)
        } else {
            MARGIN_CAP
        };
        let shift = if no_partner {
            self.no_partner_shift + self.none_margin * g
        } else {
            self.partner_margin * g
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
