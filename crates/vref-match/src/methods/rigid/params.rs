//! The constants of `rigid`, with their defaults and checks.

use serde::{Deserialize, Serialize};

use crate::MatchError;
use crate::calibration::Calibration;

/// Constants of the `rigid` method.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RigidParams {
    /// Appearance enters as `exp((a - best a of the row) / temperature)`:
    /// a likelihood relative to the row's most similar object.
    pub appearance_temperature: f64,
    /// Share of true pairs whose appearance differs between the views
    /// however similar the objects look from one side (a mug's handle, a
    /// label seen from behind): the appearance likelihood never falls
    /// below it, so appearance can weaken a pair but not veto it.
    pub appearance_floor: f64,
    /// Robot objects per human object that hypotheses are drawn from,
    /// the most similar in appearance first.
    pub candidates: usize,
    /// Distance-consistent hypotheses scored.
    pub hypotheses: usize,
    /// The same where both views know which way is up: a hypothesis is
    /// then fitted to two pairs, not three, and is all right at the
    /// chance of two right pairs, not three, so fewer are needed for the
    /// same chance of drawing a right one (docs/method.md and
    /// method-notes.md, "Gravity").
    pub hypotheses_upright: usize,
    /// Residual scale as a multiple of the robot view's median distance
    /// between nearest neighbours: position error and object spacing grow
    /// together with the range a camera works at (centimetres on a table,
    /// decimetres on a floor), so one factor serves both.
    pub sigma_factor: f64,
    /// Where the sensors state each object's position error, it is the
    /// error along the object's ray (views in camera frames), or combined
    /// with sigma in every direction (other views). False: ignored, as
    /// for dataset files, which state none.
    pub stated_errors: bool,
    /// An RGB-D camera's depth error as a share of the range, where the
    /// sensors state none: it lies along the ray from the camera (the
    /// origin of a view's frame), so a pair's residual is weighed in a
    /// metric stretched along both objects' rays, and errs far less in
    /// every other direction (`lateral_factor`). Used for views in front of
    /// their camera (every z > 0); 0 treats every direction alike (sigma).
    pub depth_error: f64,
    /// With the depth-error model: the scale of the error in every
    /// direction besides, as a multiple of the median nearest-neighbour
    /// distance (smaller than `sigma_factor`, which must cover the depth
    /// error too).
    pub lateral_factor: f64,
    /// The ray model's scales are estimated from the residuals the best
    /// motion leaves, with the assumed (or stated) scales as a prior worth
    /// this many pairs; 0 keeps the assumed scales.
    pub noise_prior: f64,
    /// Heavy tails of the residuals (the ray model): a squared Mahalanobis
    /// length `d^2` costs `tail / 2 ln(1 + d^2 / tail)`; 0 the Gaussian's
    /// `d^2 / 2`.
    pub tail: f64,
    /// Rounds of that estimate, each from the pairs the last one explains.
    pub noise_rounds: usize,

    /// Cost of leaving a human object without a partner, in the units of
    /// the pair cost `-ln(appearance likelihood) + r^2 / (2 sigma^2)`.
    pub unmatched_cost: f64,
    /// The search ends early at a hypothesis whose score reaches this
    /// share of the largest possible (every object of the smaller view
    /// explained with zero cost).
    pub decisive_share: f64,
    /// Hypotheses scored before the search may end early, for a scene of
    /// 8 x 8 objects; scaled by 64 / (n m) for others. In a scene of a few
    /// objects a wrong motion can explain nearly everything too (and its
    /// hypotheses are cheap); in a large one that is ever less likely (and
    /// each hypothesis costs n m).
    pub decisive_after: usize,
    /// Samples with short edges are drawn too whenever the search with
    /// long edges found no decisive motion (false: only when it found too
    /// few motions to keep).
    pub short_edges_always: bool,
    /// Best hypotheses of the search that are locally optimised (re-fitted
    /// to the pairs they explain) before the best is chosen.
    pub local_optimisations: usize,
    /// Re-fits of the motion on the assigned pairs after the search.
    pub refinements: usize,
    /// Score difference (in nats: scores are log-likelihood gains) that
    /// makes the best motion e times likelier than the runner-up.
    pub motion_temperature: f64,
    /// Motions that pair objects otherwise weighed against the best (1:
    /// the runner-up alone).
    pub rivals: usize,
    /// A partner that the runner-up motion pairs otherwise and whose raw
    /// share (its row's softmax share times the best motion's probability)
    /// is below this is not given: the object is answered "no partner".
    /// 0 never abstains.
    pub abstain_share: f64,
    /// Abstaining needs a real dispute: the best motion's probability
    /// against the runner-up must be below this (1 abstains whenever the
    /// runner-up pairs the row otherwise). A row share lowered by look-alike
    /// neighbours alone is not a dispute between motions.
    pub abstain_motion: f64,
    /// A motion whose evidence against chance (`coincidence::evidence`,
    /// every partner it assigns counted in its share) reaches this
    /// withholds a disputed partner only below `abstain_share_evident`
    /// instead of `abstain_share`; infinite: never.
    pub abstain_evidence: f64,
    /// The raw share below which a disputed partner of a motion whose
    /// evidence reaches `abstain_evidence` is not given.
    pub abstain_share_evident: f64,
    /// When abstention would leave a scene without any partner, the most
    /// confident disputed partner is given all the same: an empty answer is
    /// precision 0 and tells the robot nothing.
    pub never_empty: bool,
    /// Refuse motions that put the two cameras on opposite sides of the
    /// plane the objects stand on, and, where one view alone knows which
    /// way is up, the other camera clearly beneath the objects (see
    /// `Side`).
    pub same_side: bool,
    /// Hypotheses drawn to measure how many pairs a motion explains by
    /// chance in the scene; a partner is only as sure as the best motion is
    /// unlike chance (0: not measured, every motion taken as real).
    pub chance_samples: usize,
    /// The same where both views know up: the search then scores half as
    /// many hypotheses, and the null it is weighed against is sampled the
    /// same way.
    pub chance_samples_upright: usize,
    /// Rows of shuffled copies of the scene (about; whole copies, at most
    /// 64) whose cheapest pairs under the best motion measure the chance
    /// rate of the significance test (`significance.rs`); 0: not measured.
    pub chance_rows: usize,
    /// Whether a motion can be taken as chance: when its evidence
    /// (`coincidence::evidence`: its significance, plus `evidence_margin`
    /// times its score margin over chance, `evidence_share` times the
    /// share of the smaller view it pairs and `evidence_fit` times its
    /// score under the assumed noise over the largest possible) is below
    /// `evidence_floor`, its partners get at most `chance_cap` as
    /// confidence, so that they are not `ok`. Off: every motion is taken
    /// as real.
    pub chance_rule: bool,
    /// Weight of the score margin over chance in the evidence.
    pub evidence_margin: f64,
    /// Weight of the share of the smaller view paired in the evidence.
    pub evidence_share: f64,
    /// Weight of the motion's fit (its score under the assumed noise
    /// scales over the largest possible) in the evidence.
    pub evidence_fit: f64,
    /// Evidence below which a motion is taken as chance.
    pub evidence_floor: f64,
    /// The confidence a partner of a motion chance explains is capped at
    /// (below the matcher's ambiguity threshold, 0.5).
    pub chance_cap: f64,
    /// Objects both views leave unpaired under the motion are paired where
    /// their looks single each other out: each is the other's most alike
    /// by at least this appearance affinity over every other object of
    /// either view. Such a partner (an object moved between the views)
    /// gets `chance_cap` as its confidence; infinite: never.
    pub moved_look_gap: f64,
    /// The densest consistent cluster of candidate pairs (`clipper`) gives
    /// the search one more hypothesis in scenes of at most this many
    /// pairs (n x m); 0 never.
    pub clipper_seed_pairs: usize,

    /// Seed of the hypothesis sampler (answers are deterministic).
    pub seed: u64,
    /// Raw row share and fit quality to probability.
    pub calibration: Calibration,
}

impl Default for RigidParams {
    fn default() -> Self {
        Self {
            appearance_temperature: 0.2,
            appearance_floor: 0.1,
            candidates: 6,
            hypotheses: 200,
            hypotheses_upright: 100,
            sigma_factor: 0.4,
            stated_errors: true,
            depth_error: 0.065,
            lateral_factor: 0.2,
            noise_prior: 4.5,
            tail: 6.0,
            noise_rounds: 1,
            unmatched_cost: 4.5,
            decisive_share: 0.8,
            decisive_after: 100,
            short_edges_always: true,
            local_optimisations: 8,
            refinements: 3,
            motion_temperature: 1.0,
            rivals: 7,
            abstain_share: 0.65,
            abstain_motion: 0.95,
            abstain_evidence: 6.0,
            abstain_share_evident: 0.55,
            never_empty: true,
            same_side: true,
            chance_samples: 32,
            chance_samples_upright: 16,
            clipper_seed_pairs: 0,
            chance_rows: 512,
            chance_rule: true,
            evidence_margin: 0.0,
            evidence_share: 2.0,
            evidence_fit: 8.0,
            evidence_floor: 4.25,
            chance_cap: 0.45,
            moved_look_gap: 0.3,

            seed: 0x5eed,
            calibration: Calibration::default(),
        }
    }
}

impl RigidParams {
    pub(crate) fn validate(&self) -> Result<(), MatchError> {
        for (name, value) in [
            ("rigid.appearance_temperature", self.appearance_temperature),
            ("rigid.sigma_factor", self.sigma_factor),
            ("rigid.unmatched_cost", self.unmatched_cost),
            ("rigid.decisive_share", self.decisive_share),
            ("rigid.motion_temperature", self.motion_temperature),
            ("rigid.lateral_factor", self.lateral_factor),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(MatchError::BadParameter {
                    name,
                    value,
                    expected: "positive and finite",
                });
            }
        }
        for (name, count) in [
            ("rigid.candidates", self.candidates),
            ("rigid.hypotheses", self.hypotheses),
            ("rigid.hypotheses_upright", self.hypotheses_upright),
        ] {
            if count == 0 {
                return Err(MatchError::BadParameter {
                    name,
                    value: 0.0,
                    expected: "at least 1",
                });
            }
        }
        if !(self.tail == 0.0 || (self.tail.is_finite() && self.tail > 0.0)) {
            return Err(MatchError::BadParameter {
                name: "rigid.tail",
                value: self.tail,
                expected: "0 or positive and finite",
            });
        }
        if !(0.0..1.0).contains(&self.appearance_floor) {
            return Err(MatchError::BadParameter {
                name: "rigid.appearance_floor",
                value: self.appearance_floor,
                expected: "in [0, 1)",
            });
        }
        if !(self.noise_prior.is_finite() && self.noise_prior >= 0.0) {
            return Err(MatchError::BadParameter {
                name: "rigid.noise_prior",
                value: self.noise_prior,
                expected: "zero or positive and finite",
            });
        }
        if !(self.depth_error.is_finite() && self.depth_error >= 0.0) {
            return Err(MatchError::BadParameter {
                name: "rigid.depth_error",
                value: self.depth_error,
                expected: "zero or positive and finite",
            });
        }
        for (name, value) in [
            ("rigid.evidence_margin", self.evidence_margin),
            ("rigid.evidence_share", self.evidence_share),
            ("rigid.evidence_fit", self.evidence_fit),
            ("rigid.evidence_floor", self.evidence_floor),
        ] {
            if !value.is_finite() {
                return Err(MatchError::BadParameter {
                    name,
                    value,
                    expected: "finite",
                });
            }
        }
        if !(0.0..=1.0).contains(&self.chance_cap) {
            return Err(MatchError::BadParameter {
                name: "rigid.chance_cap",
                value: self.chance_cap,
                expected: "in [0, 1]",
            });
        }
        if self.moved_look_gap.is_nan() || self.moved_look_gap < 0.0 {
            return Err(MatchError::BadParameter {
                name: "rigid.moved_look_gap",
                value: self.moved_look_gap,
                expected: "zero or positive (inf: never)",
            });
        }
        if !(0.0..=1.0).contains(&self.abstain_motion) {
            return Err(MatchError::BadParameter {
                name: "rigid.abstain_motion",
                value: self.abstain_motion,
                expected: "in [0, 1]",
            });
        }
        for (name, value) in [
            ("rigid.abstain_share", self.abstain_share),
            ("rigid.abstain_share_evident", self.abstain_share_evident),
        ] {
            if !(0.0..=1.0).contains(&value) {
                return Err(MatchError::BadParameter {
                    name,
                    value,
                    expected: "in [0, 1]",
                });
            }
        }
        if self.abstain_evidence.is_nan() {
            return Err(MatchError::BadParameter {
                name: "rigid.abstain_evidence",
                value: self.abstain_evidence,
                expected: "a number (inf: never)",
            });
        }
        let c = &self.calibration;
        if ![
            c.bias,
            c.slope,
            c.no_partner_shift,
            c.partner_margin,
            c.none_margin,
        ]
        .iter()
        .all(|v| v.is_finite())
        {
            return Err(MatchError::BadParameter {
                name: "rigid.calibration",
                value: f64::NAN,
                expected: "finite constants",
            });
        }
        Ok(())
    }
}
