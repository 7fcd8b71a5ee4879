//! What one live solve of `rigid` leaves for the next: the motions its
//! search kept and what it measured of chance. A scene that changed a
//! little since (objects moved, the headset turned a little) is still
//! explained by those motions once they are re-fitted, so the next solve
//! starts from them instead of searching (the search is most of an
//! unsettled scene's solve), and reuses the margin over chance instead of
//! sampling chance again.

use super::RigidParams;
use super::costs::Costs;
use super::search::{Found, rescore};
use crate::RigidMotion;

/// A start from the last motions is kept only while its best motion scores
/// at least this share of what the last full search's best scored: a
/// scene that changed more than that gets a full search.
const KEPT_SHARE: f64 = 0.8;

/// What a solve leaves for the next solve of the same, changing scene.
#[derive(Debug, Clone)]
pub(crate) struct Track {
    /// The answer's motion, then the motions the search kept.
    pub(super) kept: Vec<RigidMotion>,
    /// The last full search's best score, under the assumed noise.
    pub(super) score: f64,
    /// Hypotheses that full search scored.
    pub(super) tests: usize,
    /// The margin over chance measured then (infinite where unmeasured).
    pub(super) margin: f64,
    /// Whether a decisive motion settled the scene then.
    pub(super) settled: bool,
}

/// The kept motions of `last` re-fitted and judged under `costs`; `None`
/// when they no longer explain the scene as well as the full search's best
/// did (at least [`KEPT_SHARE`] of its score).
pub(super) fn resume(costs: &Costs<'_>, rp: &RigidParams, last: &Track) -> Option<Found> {
    let found = rescore(costs, rp, &last.kept, last.tests)?;
    (found.score >= KEPT_SHARE * last.score).then_some(Found {
        settled: last.settled,
        ..found
    })
}

impl Track {
    /// What the solve that found `found` (its search's result) and
    /// answered with `motion` leaves; `from` is the track it resumed, if
    /// it resumed one (its full search's score, tests and margin carry
    /// over).
    pub(super) fn after(
        found: &Found,
        search_score: f64,
        motion: Option<RigidMotion>,
        margin: f64,
        from: Option<&Track>,
        keep: usize,
    ) -> Self {
        let kept = motion
            .into_iter()
            .chain(found.kept.iter().copied())
            .take(keep)
            .collect();
        match from {
            Some(t) => Self {
                kept,
                score: t.score,
                tests: t.tests,
                margin: t.margin,
                settled: t.settled,
            },
            None => Self {
                kept,
                score: search_score,
                tests: found.tests,
                margin,
                settled: found.settled,
            },
        }
    }
}
