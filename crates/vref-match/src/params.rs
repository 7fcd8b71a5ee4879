use serde::{Deserialize, Serialize};

use crate::MatchError;
use crate::{ClipperParams, RigidParams};

/// Every constant of ALGORITHMS.md, with its defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Params {
    /// Spatial bandwidth beta of Eq. 3, in squared position units.
    pub beta: f64,
    /// Sinkhorn: largest accepted deviation of a row or column sum.
    pub sinkhorn_tol: f64,
    /// Sinkhorn: most rounds.
    pub sinkhorn_max_rounds: usize,
    pub sm: SmParams,
    pub rrwm: RrwmParams,
    pub paper: PaperParams,
    /// Shortcuts of the live tier (unused by the exact tier).
    pub live: LiveParams,
    pub rigid: RigidParams,
    pub clipper: ClipperParams,
}

/// Spectral matching's power iteration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SmParams {
    /// Stop when `||v_new - v||_2` falls below this.
    pub tol: f64,
    pub max_iter: usize,
}

/// Reweighted random walks.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RrwmParams {
    /// Probability of a walk step rather than a reweighted jump.
    pub c: f64,
    /// Amplification of the jump distribution, `exp(amplification * y / max(y))`.
    pub amplification: f64,
    /// Stop when the squared change falls below this.
    pub tol: f64,
    pub max_iter: usize,
}

/// The paper's appearance-guided reweighted jumps (Algorithm 1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PaperParams {
    /// Weight of the jump term w against the appearance-driven z.
    pub alpha: f64,
    /// Weight of appearance inside w.
    pub lambda1: f64,
    /// Weight of spatial structure inside w.
    pub lambda2: f64,
    pub tol: f64,
    pub max_iter: usize,
}

/// The live tier's shortcuts (docs/performance.md says what each does
/// and costs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LiveParams {
    /// Candidate partners kept for every object at least (its most similar
    /// ones by appearance), on both sides.
    pub candidates_min: usize,
    /// Candidate partners kept for a human object at most.
    pub candidates_max: usize,
    /// Partners whose appearance affinity is within this of the object's
    /// best are kept too (up to `candidates_max`), so look-alikes all stay
    /// candidates.
    pub appearance_margin: f64,
    /// Stop once every row's best partner has not changed for this many
    /// iterations.
    pub stable_iterations: usize,
    /// Most Sinkhorn rounds per normalisation. On the pruned pairs the
    /// support is sparse and Sinkhorn may creep towards its tolerance for
    /// hundreds of rounds (RRWM's sharp jumps especially).
    pub sinkhorn_max_rounds: usize,
    /// `rigid`: one solve in this many is a full search; the others start
    /// from the motions the last solve kept, re-fitted to the changed
    /// scene, while those still explain it (docs/method.md, "Solve
    /// time"). A full search every so often keeps a wrong motion from
    /// lasting. 0 or 1: every solve is a full search.
    pub rigid_full_every: usize,
    /// `rigid`: the full search that falls due runs on a thread of its
    /// own while solves go on resuming, and the first solve after it ends
    /// takes up its motions (one still running two periods after the
    /// last full search gives way to a search in the solve); `false`: it
    /// runs in the solve that falls due, which then takes as long as a
    /// full search.
    pub rigid_full_apart: bool,
}

impl Default for LiveParams {
    fn default() -> Self {
        Self {
            candidates_min: 4,
            candidates_max: 10,
            appearance_margin: 0.2,
            stable_iterations: 3,
            sinkhorn_max_rounds: 30,
            rigid_full_every: 20,
            rigid_full_apart: true,
        }
    }
}

impl Default for Params {
    fn default() -> Self {
        Self {
            beta: 0.01,
            sinkhorn_tol: 1e-3,
            sinkhorn_max_rounds: 1000,
            sm: SmParams::default(),
            rrwm: RrwmParams::default(),
            paper: PaperParams::default(),
            live: LiveParams::default(),
            rigid: RigidParams::default(),
            clipper: ClipperParams::default(),
        }
    }
}

impl Default for SmParams {
    fn default() -> Self {
        Self {
            tol: 1e-9,
            max_iter: 1000,
        }
    }
}

impl Default for RrwmParams {
    fn default() -> Self {
        Self {
            c: 0.2,
            amplification: 30.0,
            tol: 1e-20,
            max_iter: 300,
        }
    }
}

impl Default for PaperParams {
    fn default() -> Self {
        Self {
            alpha: 0.3,
            lambda1: 0.5,
            lambda2: 0.5,
            tol: 1e-20,
            max_iter: 300,
        }
    }
}

impl Params {
    /// The constants the live tier runs with: these, with Sinkhorn capped
    /// at `live.sinkhorn_max_rounds`.
    pub fn for_live(&self) -> Params {
        Params {
            sinkhorn_max_rounds: self.sinkhorn_max_rounds.min(self.live.sinkhorn_max_rounds),
            ..*self
        }
    }

    /// Refuses values the methods are not defined for.
    pub fn validate(&self) -> Result<(), MatchError> {
        positive("beta", self.beta)?;
        positive("sinkhorn_tol", self.sinkhorn_tol)?;
        positive("sm.tol", self.sm.tol)?;
        positive("rrwm.tol", self.rrwm.tol)?;
        positive("paper.tol", self.paper.tol)?;
        unit("rrwm.c", self.rrwm.c)?;
        unit("paper.alpha", self.paper.alpha)?;
        unit("paper.lambda1", self.paper.lambda1)?;
        unit("paper.lambda2", self.paper.lambda2)?;
        self.rigid.validate()?;
        self.clipper.validate()?;
        // exp(amplification) must stay finite after Sinkhorn's products.
        if !(self.rrwm.amplification > 0.0 && self.rrwm.amplification <= 300.0) {
            return Err(MatchError::BadParameter {
                name: "rrwm.amplification",
                value: self.rrwm.amplification,
                expected: "in (0, 300]",
            });
        }
        if !(self.live.appearance_margin.is_finite() && self.live.appearance_margin >= 0.0) {
            return Err(MatchError::BadParameter {
                name: "live.appearance_margin",
                value: self.live.appearance_margin,
                expected: "non-negative and finite",
            });
        }
        if self.live.candidates_max < self.live.candidates_min {
            return Err(MatchError::BadParameter {
                name: "live.candidates_max",
                value: self.live.candidates_max as f64,
                expected: "at least live.candidates_min",
            });
        }
        for (name, count) in [
            ("sinkhorn_max_rounds", self.sinkhorn_max_rounds),
            ("sm.max_iter", self.sm.max_iter),
            ("rrwm.max_iter", self.rrwm.max_iter),
            ("paper.max_iter", self.paper.max_iter),
            ("live.candidates_min", self.live.candidates_min),
            ("live.candidates_max", self.live.candidates_max),
            ("live.stable_iterations", self.live.stable_iterations),
            ("live.sinkhorn_max_rounds", self.live.sinkhorn_max_rounds),
        ] {
            if count == 0 {
                return Err(MatchError::BadParameter {
                    name,
                    value: 0.0,
                    expected: "at least 1",
                });
            }
        }
        Ok(())
    }
}

fn positive(name: &'static str, value: f64) -> Result<(), MatchError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(MatchError::BadParameter {
            name,
            value,
            expected: "positive and finite",
        })
    }
}

fn unit(name: &'static str, value: f64) -> Result<(), MatchError> {
    if (0.0..=1.0).contains(&value) {
        Ok(())
    } else {
        Err(MatchError::BadParameter {
            name,
            value,
            expected: "in [0, 1]",
        })
    }
}
