//! `rigid` in the live tier: a full search every `rigid_full_every`
//! solves, else a start from the motions the last solve kept. With
//! `rigid_full_apart` the search that falls due runs on a thread of its
//! own while solves go on resuming.
//!
//! Motions belong to the scene they were found in. A start from them is
//! only tried while most of each view's objects (by track id) are ones
//! that scene had: a view swapped for another scene (a dataset's next
//! scene, a feed restarted) is searched at once, even where the old
//! motions happen to fit it, and so is the scene after a half-swapped
//! one, whose motions were found between two scenes.

use std::collections::HashSet;

use super::background::Search;
use crate::methods::{RigidTrack, rigid_solve_from};
use crate::{Params, Problem, Solution};

/// A start from kept motions needs at least this share of each view's
/// objects to have been in the views they were found in.
const SAME_SCENE_SHARE: f64 = 0.5;

/// A search apart gives way to one on the solve's thread once this many
/// `rigid_full_every` periods have passed without a full search: a wrong
/// motion lasts at most twice as many solves as without searches apart.
const OVERDUE_PERIODS: usize = 2;

/// The track ids of the two views a full search searched.
#[derive(Debug, Clone, Default)]
pub(super) struct SceneIds {
    human: HashSet<u64>,
    robot: HashSet<u64>,
}

impl SceneIds {
    pub(super) fn of(human: &[u64], robot: &[u64]) -> Self {
        Self {
            human: human.iter().copied().collect(),
            robot: robot.iter().copied().collect(),
        }
    }

    /// Whether views of these ids show the scene `self` was taken of.
    fn holds(&self, human: &[u64], robot: &[u64]) -> bool {
        let share = |seen: &HashSet<u64>, ids: &[u64]| {
            let known = ids.iter().filter(|id| seen.contains(id)).count();
            known as f64 >= SAME_SCENE_SHARE * ids.len() as f64
        };
        share(&self.human, human) && share(&self.robot, robot)
    }
}

/// What `rigid`'s live solves carry from one to the next.
#[derive(Debug, Clone, Default)]
pub(super) struct Resumer {
    /// What the last solve left for the next, and the views its motions
    /// were found in.
    track: Option<RigidTrack>,
    scene: SceneIds,
    /// Solves since the last full search.
    resumed_solves: usize,
    /// Whether the last solve resumed.
    pub(super) last_resumed: bool,
    /// Full searches so far, counting one apart once taken up.
    pub(super) full_searches: u64,
    /// The full search running apart, if any.
    search: Option<Search>,
    /// What a search apart runs first on its thread.
    pub(super) begin: Option<fn()>,
}

impl Resumer {
    /// Solves `problem`, whose rows and columns stand for `human` and
    /// `robot`.
    pub(super) fn solve(
        &mut self,
        problem: &Problem,
        params: &Params,
        human: &[u64],
        robot: &[u64],
    ) -> Solution {
        self.take_up(false);
        let same_scene = self.scene.holds(human, robot);
        let full_every = params.live.rigid_full_every;
        let due = self.resumed_solves + 1 >= full_every;
        // A search apart still running long after it fell due (its thread
        // starved by a busy machine) gives way to one on this thread, so
        // that a wrong motion cannot last for ever.
        let overdue = self.resumed_solves + 1 >= OVERDUE_PERIODS * full_every;
        if due
            && same_scene
            && params.live.rigid_full_apart
            && full_every > 1
            && self.track.is_some()
            && self.search.is_none()
        {
            self.search = Search::start(
                problem.clone(),
                *params,
                self.full_searches,
                SceneIds::of(human, robot),
                self.begin,
            );
        }
        let last = self
            .track
            .as_ref()
            .filter(|_| same_scene && !overdue && (!due || self.search.is_some()));
        let (solution, track, resumed) = rigid_solve_from(problem, params, last);
        self.last_resumed = resumed;
        if resumed {
            self.resumed_solves += 1;
        } else {
            self.resumed_solves = 0;
            self.full_searches += 1;
            self.scene = SceneIds::of(human, robot);
        }
        self.track = track;
        solution
    }

    /// Whether a search apart has ended whose motions the next solve
    /// would take up: a solve would give something new, though neither
    /// view changed.
    pub(super) fn has_news(&self) -> bool {
        self.search
            .as_ref()
            .is_some_and(|s| s.generation == self.full_searches && s.has_ended())
    }

    /// Takes up the motions of the full search running apart once it has
    /// ended (with `wait`, once it ends), unless a full search on the
    /// solve's own thread came after it started.
    pub(super) fn take_up(&mut self, wait: bool) {
        let Some(track) = self.search.as_ref().and_then(|s| s.ended(wait)) else {
            return;
        };
        let Some(search) = self.search.take() else {
            return;
        };
        if search.generation == self.full_searches
            && let Some(track) = track
        {
            self.track = Some(track);
            self.scene = search.scene;
            self.resumed_solves = 0;
            self.full_searches += 1;
        }
    }
}
