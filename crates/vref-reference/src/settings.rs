use serde::{Deserialize, Serialize};
use vref_match::{Method, OkRule, Tier};

/// The `[matcher]` section of config/vref.toml.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MatcherSettings {
    /// Matching method the service uses (appearance, sm, rrwm, paper,
    /// rigid).
    pub method: String,
    /// Solver tier: `live` (candidate pairs pruned by appearance, early
    /// stop, warm start across snapshots) or `exact` (ALGORITHMS.md).
    pub tier: String,
    /// Answers resting on a snapshot captured longer ago than this (its
    /// `timestamp_ns` against this machine's clock) are `stale`, ms. Half
    /// of it is the freshness budget a solve at `[scene] capacity` must fit
    /// (crate::budget).
    pub stale_after_ms: u64,
    /// Latest-gesture answers resting on a ray captured longer ago than
    /// this are `stale`, ms.
    pub ray_max_age_ms: u64,
    /// How far a publisher's clock may run ahead of this one's: a message
    /// stamped further in the future is refused, one within it counts as
    /// captured now, ms.
    pub max_clock_skew_ms: u64,
    /// A message stamped longer ago than this is refused: no feed delivers
    /// that late, so the stamp is wrong, ms.
    pub max_capture_age_ms: u64,
    /// Queries a client may have answered per second (bursts of a tenth of
    /// a second's worth); the rest are dropped unanswered and counted.
    pub max_queries_per_client_hz: f64,
    /// Nice value of the solver thread (0 to 19): above 0 the query path,
    /// the feeds and the clients run first, and the solve takes what CPU
    /// is left (all of a core on a machine with one to spare).
    pub solver_nice: i32,
    /// How often dead nodes of crashed processes are cleaned up, ms.
    pub cleanup_interval_ms: u64,
    /// A snapshot whose feature length differs from the other side's is
    /// taken (and the other side's dropped) once its side has sent that
    /// length for this long while the other side had nothing accepted,
    /// ms: a source replaced on one side is not locked out by a snapshot
    /// its old peer left behind. Without waiting, when the other side has
    /// itself been refused for sending this snapshot's length (both
    /// sources replaced).
    pub feature_dim_grace_ms: u64,
    /// Answers whose confidence is below this are `ambiguous` (with the
    /// top alternatives). `rigid`'s confidence is a calibrated probability
    /// that the answer is right, so the default 0.5 flags answers more
    /// likely wrong than right; the published methods' confidence is only
    /// a row share (docs/method.md).
    pub ambiguity_threshold: f64,
    /// A partner whose pair leaves a residual under the answer's motion
    /// larger than this, in squared units of both objects' stated position
    /// errors, is `ambiguous`, not `ok`, however confident; pairs of
    /// objects stating no error are not tested. The default 70.4 fails a
    /// right pair once in a thousand where the errors are as stated with
    /// the heavy tails `rigid` models (a three-dimensional Student t with 6
    /// degrees of freedom); `inf` turns the test off.
    pub fit_limit: f64,
}

impl MatcherSettings {
    /// When an answer is `ok`.
    pub fn ok_rule(&self) -> OkRule {
        OkRule {
            ambiguity_threshold: self.ambiguity_threshold,
            fit_limit: self.fit_limit,
        }
    }
}

impl Default for MatcherSettings {
    fn default() -> Self {
        Self {
            method: "rigid".to_owned(),
            tier: "live".to_owned(),
            stale_after_ms: 500,
            ray_max_age_ms: 2000,
            max_clock_skew_ms: 100,
            max_capture_age_ms: 10_000,
            max_queries_per_client_hz: 2000.0,
            solver_nice: 10,
            cleanup_interval_ms: 250,
            feature_dim_grace_ms: 1000,
            ambiguity_threshold: OkRule::default().ambiguity_threshold,
            fit_limit: OkRule::default().fit_limit,
        }
    }
}

impl MatcherSettings {
    /// The configured method, or an error naming the bad value.
    pub fn method(&self) -> Result<Method, vref_match::MatchError> {
        self.method.parse()
    }

    /// The configured tier, or an error naming the bad value.
    pub fn tier(&self) -> Result<Tier, vref_match::MatchError> {
        self.tier.parse()
    }
}
