use serde::{Deserialize, Serialize};
use vref_match::{Method, Tier};

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
    /// A feed silent for longer makes answers `stale`, milliseconds.
    pub stale_after_ms: u64,
    /// How often dead nodes of crashed processes are cleaned up, ms.
    pub cleanup_interval_ms: u64,
    /// Answers whose confidence is below this are `ambiguous` (with the
    /// top alternatives). `rigid`'s confidence is a calibrated probability
    /// that the answer is right, so the default 0.5 flags answers more
    /// likely wrong than right; the published methods' confidence is only
    /// a row share (README).
    pub ambiguity_threshold: f64,
}

impl Default for MatcherSettings {
    fn default() -> Self {
        Self {
            method: "rigid".to_owned(),
            tier: "live".to_owned(),
            stale_after_ms: 500,
            cleanup_interval_ms: 250,
            ambiguity_threshold: 0.5,
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
