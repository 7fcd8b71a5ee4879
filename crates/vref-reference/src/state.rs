use std::sync::Arc;
use std::time::{Duration, Instant};

use vref_match::MatchError;
use vref_scene::{Limits, Side};
use vref_wire::{ObjectEntry, PointingRay, Ray, SnapshotHeader, ValidSnapshot, validate_snapshot};

use crate::sequence::{Origin, Placement, Sequencer};
use crate::solver::{Pair, Solved};
use crate::stamp::{Now, StampLimits};
use crate::{MatcherSettings, RejectReason, Rejections};

/// A message refused, with the counter it went to and what was wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{reason}: {detail}")]
pub struct Rejected {
    pub reason: RejectReason,
    pub detail: String,
}

/// A message taken: how it fits its publisher's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Accepted {
    pub placement: Placement,
}

/// What the matcher's intake and query path know: the newest accepted
/// snapshot of each side and pointing ray, and the latest finished
/// solution (with the snapshots it was solved for), which is what queries
/// read. Solving happens elsewhere ([`crate::Solver`]); this never waits
/// for it.
#[derive(Debug)]
pub struct ReferenceState {
    pub(crate) limits: Limits,
    pub(crate) stale_after: Duration,
    pub(crate) ray_max_age: Duration,
    pub(crate) ok_rule: vref_match::OkRule,
    stamps: StampLimits,
    robot: Option<Arc<ValidSnapshot>>,
    human: Option<Arc<ValidSnapshot>>,
    pub(crate) gesture: Option<Ray>,
    pub(crate) solved: Option<Arc<Solved>>,
    /// Robot snapshots, human snapshots, rays.
    order: [Sequencer; 3],
    /// When each side's snapshot in force was accepted.
    accepted_at: [Option<Instant>; 2],
    /// The feature length each side was last refused for, as
    /// `feature_dim_other_side`, and since when it has been, since its
    /// last accepted snapshot.
    dim_refused: [Option<(usize, Instant)>; 2],
    feature_dim_grace: Duration,
    /// Each side's latest refused snapshot's reason, since its last
    /// accepted one: what a stale or not-ready answer names.
    last_refused: [Option<RejectReason>; 2],
    rejections: Rejections,
}

const RAYS: usize = 2;

impl ReferenceState {
    pub fn new(settings: &MatcherSettings, limits: Limits) -> Result<Self, MatchError> {
        settings.method()?;
        settings.tier()?;
        let stale_after = Duration::from_millis(settings.stale_after_ms);
        // A feed locked out this long would have made answers stale anyway.
        let order = || Sequencer::new(stale_after);
        Ok(Self {
            limits,
            stale_after,
            ray_max_age: Duration::from_millis(settings.ray_max_age_ms),
            ok_rule: settings.ok_rule(),
            stamps: StampLimits {
                max_skew: Duration::from_millis(settings.max_clock_skew_ms),
                max_age: Duration::from_millis(settings.max_capture_age_ms),
            },
            robot: None,
            human: None,
            gesture: None,
            solved: None,
            order: [order(), order(), order()],
            accepted_at: [None; 2],
            dim_refused: [None; 2],
            feature_dim_grace: Duration::from_millis(settings.feature_dim_grace_ms),
            last_refused: [None; 2],
            rejections: Rejections::default(),
        })
    }

    /// Takes a snapshot read from `side`'s service, sent by publisher port
    /// `origin`, or refuses it (counted) and keeps the last good one.
    pub fn accept_snapshot(
        &mut self,
        side: Side,
        origin: Origin,
        header: &SnapshotHeader,
        entries: &[ObjectEntry],
        now: &Now,
    ) -> Result<Accepted, Rejected> {
        let result = self.check_snapshot(side, origin, header, entries, now);
        match result {
            Ok((snapshot, placement, replaces_other)) => {
                self.order[side as usize].record(
                    origin,
                    snapshot.session,
                    snapshot.sequence,
                    now.instant,
                );
                if replaces_other {
                    // Its features cannot be compared with this one's: the
                    // other side waits for a snapshot of the new length.
                    let other = other_side(side);
                    *self.slot(other) = None;
                    self.accepted_at[other as usize] = None;
                }
                *self.slot(side) = Some(Arc::new(snapshot));
                self.accepted_at[side as usize] = Some(now.instant);
                self.dim_refused[side as usize] = None;
                self.last_refused[side as usize] = None;
                Ok(Accepted { placement })
            }
            Err(rejected) => {
                self.last_refused[side as usize] = Some(rejected.reason);
                if rejected.reason == RejectReason::FeatureDimOtherSide {
                    let dim = header.feature_dim as usize;
                    let refused = &mut self.dim_refused[side as usize];
                    match refused {
                        Some((d, _)) if *d == dim => {}
                        _ => *refused = Some((dim, now.instant)),
                    }
                }
                self.rejections.count(rejected.reason);
                Err(rejected)
            }
        }
    }

    fn slot(&mut self, side: Side) -> &mut Option<Arc<ValidSnapshot>> {
        match side {
            Side::Robot => &mut self.robot,
            Side::Human => &mut self.human,
        }
    }

    fn check_snapshot(
        &mut self,
        side: Side,
        origin: Origin,
        header: &SnapshotHeader,
        entries: &[ObjectEntry],
        now: &Now,
    ) -> Result<(ValidSnapshot, Placement, bool), Rejected> {
        let snapshot =
            validate_snapshot(header, entries, side, &self.limits).map_err(|e| Rejected {
                reason: RejectReason::of(&e),
                detail: e.to_string(),
            })?;
        self.stamps.check(snapshot.timestamp_ns, now)?;
        let replaces_other = self.other_length(side, snapshot.graph.feature_dim(), now)?;
        // Last: only a message that would otherwise be taken may count
        // towards its port's resynchronisation.
        let placement = self.order[side as usize].place(
            origin,
            snapshot.session,
            snapshot.sequence,
            now.instant,
        )?;
        Ok((snapshot, placement, replaces_other))
    }

    /// Whether a snapshot of `side` with feature length `mine` fits the
    /// other side's snapshot in force: `Ok(false)` if it does, `Ok(true)`
    /// if it replaces a length the other side no longer stands by (it
    /// agrees to `mine`, or has been silent for the grace), else refused.
    fn other_length(&self, side: Side, mine: usize, now: &Now) -> Result<bool, Rejected> {
        let other = other_side(side);
        let Some(theirs) = self.snapshot(other).map(|s| s.graph.feature_dim()) else {
            return Ok(false);
        };
        if mine == 0 || theirs == 0 || mine == theirs {
            return Ok(false);
        }
        let grace = self.feature_dim_grace;
        let over = |since: Instant| now.instant.saturating_duration_since(since) >= grace;
        let agrees = self.dim_refused[other as usize].is_some_and(|(d, _)| d == mine);
        // One message is no new source (an injected or stray one): the
        // new length must have been sent for the grace, while the other
        // side sent nothing.
        let insists =
            self.dim_refused[side as usize].is_some_and(|(d, since)| d == mine && over(since));
        let silent = self.accepted_at[other as usize].is_none_or(over);
        if agrees || (insists && silent) {
            return Ok(true);
        }
        Err(Rejected {
            reason: RejectReason::FeatureDimOtherSide,
            detail: format!(
                "feature dimension {mine}, the other side's is {theirs} (taken once the other side sends {mine} too, or once this side has sent {mine} for {} ms while the other sent nothing)",
                grace.as_millis()
            ),
        })
    }

    /// Takes a pointing ray sent by publisher port `origin`, or refuses it
    /// (counted).
    pub fn accept_ray(
        &mut self,
        origin: Origin,
        ray: &PointingRay,
        now: &Now,
    ) -> Result<Accepted, Rejected> {
        let checked = ray
            .validate()
            .map_err(|e| Rejected {
                reason: RejectReason::of(&e),
                detail: e.to_string(),
            })
            .and_then(|r| {
                self.stamps.check(r.timestamp_ns, now)?;
                let placement =
                    self.order[RAYS].place(origin, r.session, r.sequence, now.instant)?;
                Ok((r, placement))
            });
        match checked {
            Ok((r, placement)) => {
                self.order[RAYS].record(origin, r.session, r.sequence, now.instant);
                self.gesture = Some(r);
                Ok(Accepted { placement })
            }
            Err(rejected) => {
                self.rejections.count(rejected.reason);
                Err(rejected)
            }
        }
    }

    /// The newest accepted snapshot of each side, once both have one.
    pub fn latest_pair(&self) -> Option<Pair> {
        Some(Pair {
            robot: self.robot.clone()?,
            human: self.human.clone()?,
        })
    }

    /// Makes `solved` the solution queries read; returns the one it
    /// replaces, so the caller can free it off the query path.
    pub fn install(&mut self, solved: Arc<Solved>) -> Option<Arc<Solved>> {
        self.solved.replace(solved)
    }

    /// The solution queries read now.
    pub fn solution(&self) -> Option<&Solved> {
        self.solved.as_deref()
    }

    /// Real solves behind the solution queries read now.
    pub fn solves(&self) -> u64 {
        self.solved.as_ref().map_or(0, |s| s.solves)
    }

    pub fn rejections(&self) -> &Rejections {
        &self.rejections
    }

    /// Counts a refusal made outside this state (a query over its
    /// client's rate).
    pub fn count_rejection(&mut self, reason: RejectReason) {
        self.rejections.count(reason);
    }

    /// The last valid snapshot of a side.
    pub fn snapshot(&self, side: Side) -> Option<&ValidSnapshot> {
        match side {
            Side::Robot => self.robot.as_deref(),
            Side::Human => self.human.as_deref(),
        }
    }

    /// The reason of `side`'s latest refused snapshot, if none was
    /// accepted after it.
    pub fn last_refused(&self, side: Side) -> Option<RejectReason> {
        self.last_refused[side as usize]
    }

    pub fn latest_ray(&self) -> Option<&Ray> {
        self.gesture.as_ref()
    }
}

fn other_side(side: Side) -> Side {
    match side {
        Side::Robot => Side::Human,
        Side::Human => Side::Robot,
    }
}
