use std::fmt;
use std::str::FromStr;

use crate::MatchError;

/// How a method is run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Tier {
    /// The definitions of ALGORITHMS.md: every candidate pair, a cold
    /// start, iterations until the method's own tolerance.
    #[default]
    Exact,
    /// What the matcher serves: candidate pairs pruned by appearance, a
    /// stop once the assignment has been stable for a few iterations, and
    /// a warm start from the previous solution when there is one.
    Live,
}

impl Tier {
    pub const ALL: [Tier; 2] = [Tier::Exact, Tier::Live];

    pub fn name(self) -> &'static str {
        match self {
            Tier::Exact => "exact",
            Tier::Live => "live",
        }
    }
}

impl fmt::Display for Tier {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Tier {
    type Err = MatchError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Tier::ALL
            .into_iter()
            .find(|t| t.name() == s)
            .ok_or_else(|| MatchError::UnknownTier(s.to_owned()))
    }
}
