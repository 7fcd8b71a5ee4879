use std::time::{Duration, Instant};

use vref_match::engine::Engine;
use vref_match::{MatchError, Params};
use vref_scene::{Limits, Side};
use vref_wire::{ObjectEntry, PointingRay, Ray, SnapshotHeader, ValidSnapshot, validate_snapshot};

use crate::{MatcherSettings, RejectReason, Rejections};

/// A message refused, with the counter it went to and what was wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{reason}: {detail}")]
pub struct Rejected {
    pub reason: RejectReason,
    pub detail: String,
}

#[derive(Debug, Clone)]
pub(crate) struct Feed {
    pub snapshot: ValidSnapshot,
    pub received_at: Instant,
}

/// The pair of snapshots the engine's solution is for, each named by its
/// (session, sequence). The solution itself stays in the engine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Cached {
    pub robot: SnapshotKey,
    pub human: SnapshotKey,
}

/// A snapshot's (session, sequence).
type SnapshotKey = (u64, u64);

/// Everything the matcher knows.
#[derive(Debug)]
pub struct ReferenceState {
    pub(crate) limits: Limits,
    pub(crate) stale_after: Duration,
    pub(crate) ambiguity_threshold: f64,
    pub(crate) robot: Option<Feed>,
    pub(crate) human: Option<Feed>,
    pub(crate) gesture: Option<Ray>,
    pub(crate) cached: Option<Cached>,
    /// Incremental solver, holding the solution `cached` names; `fed_*`
    /// name the snapshots it holds.
    pub(crate) engine: Engine,
    fed_robot: Option<SnapshotKey>,
    fed_human: Option<SnapshotKey>,
    rejections: Rejections,
    solves: u64,
}

impl ReferenceState {
    pub fn new(
        settings: &MatcherSettings,
        params: Params,
        limits: Limits,
    ) -> Result<Self, MatchError> {
        params.validate()?;
        let method = settings.method()?;
        Ok(Self {
            engine: Engine::new(method, settings.tier()?, params)?,
            fed_robot: None,
            fed_human: None,
            limits,
            stale_after: Duration::from_millis(settings.stale_after_ms),
            ambiguity_threshold: settings.ambiguity_threshold,
            robot: None,
            human: None,
            gesture: None,
            cached: None,
            rejections: Rejections::default(),
            solves: 0,
        })
    }

    /// Takes a snapshot read from `side`'s service, or refuses it (counted)
    /// and keeps the last good one.
    pub fn accept_snapshot(
        &mut self,
        side: Side,
        header: &SnapshotHeader,
        entries: &[ObjectEntry],
        now: Instant,
    ) -> Result<(), Rejected> {
        let result = self.check_snapshot(side, header, entries);
        match result {
            Ok(snapshot) => {
                let feed = Some(Feed {
                    snapshot,
                    received_at: now,
                });
                match side {
                    Side::Robot => self.robot = feed,
                    Side::Human => self.human = feed,
                }
                Ok(())
            }
            Err(rejected) => {
                self.rejections.count(rejected.reason);
                Err(rejected)
            }
        }
    }

    fn check_snapshot(
        &self,
        side: Side,
        header: &SnapshotHeader,
        entries: &[ObjectEntry],
    ) -> Result<ValidSnapshot, Rejected> {
        let snapshot =
            validate_snapshot(header, entries, side, &self.limits).map_err(|e| Rejected {
                reason: RejectReason::of(&e),
                detail: e.to_string(),
            })?;
        let (own, other) = match side {
            Side::Robot => (&self.robot, &self.human),
            Side::Human => (&self.human, &self.robot),
        };
        if let Some(last) = own
            && last.snapshot.session == snapshot.session
            && snapshot.sequence <= last.snapshot.sequence
        {
            return Err(Rejected {
                reason: RejectReason::SequenceBackwards,
                detail: format!(
                    "sequence {} after {} in the same session",
                    snapshot.sequence, last.snapshot.sequence
                ),
            });
        }
        if let Some(other) = other {
            let (mine, theirs) = (
                snapshot.graph.feature_dim(),
                other.snapshot.graph.feature_dim(),
            );
            if mine != 0 && theirs != 0 && mine != theirs {
                return Err(Rejected {
                    reason: RejectReason::FeatureDimOtherSide,
                    detail: format!("feature dimension {mine}, the other side's is {theirs}"),
                });
            }
        }
        Ok(snapshot)
    }

    /// Takes a pointing ray, or refuses it (counted).
    pub fn accept_ray(&mut self, ray: &PointingRay) -> Result<(), Rejected> {
        let checked = ray.validate().map_err(|e| Rejected {
            reason: RejectReason::of(&e),
            detail: e.to_string(),
        });
        let checked = checked.and_then(|r| match &self.gesture {
            Some(last) if last.session == r.session && r.sequence <= last.sequence => {
                Err(Rejected {
                    reason: RejectReason::SequenceBackwards,
                    detail: format!("ray sequence {} after {}", r.sequence, last.sequence),
                })
            }
            _ => Ok(r),
        });
        match checked {
            Ok(r) => {
                self.gesture = Some(r);
                Ok(())
            }
            Err(rejected) => {
                self.rejections.count(rejected.reason);
                Err(rejected)
            }
        }
    }

    /// Solves for the latest pair of snapshots unless the cached solution
    /// is already theirs. Returns whether a solve ran.
    pub fn refresh(&mut self) -> Result<bool, MatchError> {
        let (Some(robot), Some(human)) = (&self.robot, &self.human) else {
            return Ok(false);
        };
        let key = |f: &Feed| (f.snapshot.session, f.snapshot.sequence);
        let (rk, hk) = (key(robot), key(human));
        if self
            .cached
            .as_ref()
            .is_some_and(|c| c.robot == rk && c.human == hk)
        {
            return Ok(false);
        }
        // The engine diffs each new snapshot by track id against the one
        // it holds, so only changed objects cost work.
        if self.fed_robot != Some(rk) {
            self.engine.update(Side::Robot, &robot.snapshot.graph)?;
            self.fed_robot = Some(rk);
        }
        if self.fed_human != Some(hk) {
            self.engine.update(Side::Human, &human.snapshot.graph)?;
            self.fed_human = Some(hk);
        }
        self.engine.solve()?;
        self.cached = Some(Cached {
            robot: rk,
            human: hk,
        });
        self.solves += 1;
        Ok(true)
    }

    pub fn rejections(&self) -> &Rejections {
        &self.rejections
    }

    /// Solves run so far.
    pub fn solves(&self) -> u64 {
        self.solves
    }

    /// The last valid snapshot of a side.
    pub fn snapshot(&self, side: Side) -> Option<&ValidSnapshot> {
        match side {
            Side::Robot => self.robot.as_ref(),
            Side::Human => self.human.as_ref(),
        }
        .map(|f| &f.snapshot)
    }

    /// How long ago the last valid snapshot of `side` arrived.
    pub fn age(&self, side: Side, now: Instant) -> Option<Duration> {
        match side {
            Side::Robot => self.robot.as_ref(),
            Side::Human => self.human.as_ref(),
        }
        .map(|f| now.saturating_duration_since(f.received_at))
    }

    pub fn latest_ray(&self) -> Option<&Ray> {
        self.gesture.as_ref()
    }
}
