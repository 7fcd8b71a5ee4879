//! The solve, apart from intake and queries: it takes a pair of accepted
//! snapshots and gives back a finished solution that names them. The
//! service runs it on its own thread.

use std::sync::Arc;
use std::time::{Duration, Instant};

use vref_match::engine::Engine;
use vref_match::{MatchError, Method, Params, Solution};
use vref_scene::Side;
use vref_wire::ValidSnapshot;

use crate::MatcherSettings;
use crate::stamp::Now;

/// The newest accepted snapshot of each side, to be solved.
#[derive(Debug, Clone)]
pub struct Pair {
    pub robot: Arc<ValidSnapshot>,
    pub human: Arc<ValidSnapshot>,
}

/// A finished solution and the snapshots it was solved for: everything a
/// query reads.
#[derive(Debug, Clone)]
pub struct Solved {
    pub robot: Arc<ValidSnapshot>,
    pub human: Arc<ValidSnapshot>,
    /// Rows: `human`'s objects in order; columns: `robot`'s.
    pub solution: Solution,
    /// Whether a real solve made `solution`; `false` when both snapshots
    /// held exactly the objects of the last solve's, whose solution is
    /// carried over.
    pub real: bool,
    /// Real solves so far, this one included.
    pub solves: u64,
    pub finished: Now,
    /// How long the solve (or the check that none was needed) took.
    pub took: Duration,
}

/// A snapshot's (session, sequence).
type Key = (u64, u64);

/// The engine and which snapshots it holds.
#[derive(Debug)]
pub struct Solver {
    engine: Engine,
    params: Params,
    search_begin: Option<fn()>,
    fed: [Option<Key>; 2],
    last: Option<Solution>,
    solves: u64,
}

impl Solver {
    pub fn new(settings: &MatcherSettings, params: Params) -> Result<Self, MatchError> {
        params.validate()?;
        Ok(Self {
            engine: Engine::new(settings.method()?, settings.tier()?, params)?,
            params,
            search_begin: None,
            fed: [None; 2],
            last: None,
            solves: 0,
        })
    }

    /// A fresh engine: both sides' feature length changed (the intake
    /// takes such a pair, ReferenceState), which the engine, fed one side
    /// at a time, would refuse against the other side it still holds.
    fn restart(&mut self) -> Result<(), MatchError> {
        self.engine = Engine::new(self.engine.method(), self.engine.tier(), self.params)?;
        if let Some(begin) = self.search_begin {
            self.engine.on_search_thread(begin);
        }
        self.fed = [None; 2];
        self.last = None;
        Ok(())
    }

    pub fn method(&self) -> Method {
        self.engine.method()
    }

    /// Has `begin` run first on the thread of every full search the
    /// engine runs apart (`[matching.live] rigid_full_apart`).
    pub fn on_search_thread(&mut self, begin: fn()) {
        self.search_begin = Some(begin);
        self.engine.on_search_thread(begin);
    }

    /// Real solves so far.
    pub fn solves(&self) -> u64 {
        self.solves
    }

    /// Gives the engine the snapshots of `pair` it does not hold yet.
    fn feed(&mut self, pair: &Pair) -> Result<(), MatchError> {
        for (side, snapshot) in [(Side::Robot, &pair.robot), (Side::Human, &pair.human)] {
            let key = Some((snapshot.session, snapshot.sequence));
            if self.fed[side as usize] != key {
                // Forget what was fed first: a failed update leaves the
                // engine's view of this side unknown.
                self.fed[side as usize] = None;
                self.engine.update(side, &snapshot.graph)?;
                self.fed[side as usize] = key;
            }
        }
        Ok(())
    }

    /// Solves `pair`; the engine diffs each snapshot by track id against
    /// the one it holds, so only changed objects cost work, and unchanged
    /// objects cost no solve at all.
    pub fn solve(&mut self, pair: &Pair) -> Result<Solved, MatchError> {
        let started = Instant::now();
        match self.feed(pair) {
            Err(MatchError::FeatureDimsDiffer { .. }) => {
                self.restart()?;
                self.feed(pair)?;
            }
            fed => fed?,
        }
        let real = self.engine.is_dirty() || self.last.is_none();
        if real {
            let (solution, _, _) = self.engine.solve()?;
            self.last = Some(solution.clone());
            self.solves += 1;
        }
        let solution = self
            .last
            .clone()
            .ok_or(MatchError::EmptyGraph { side: "human" })?;
        Ok(Solved {
            robot: pair.robot.clone(),
            human: pair.human.clone(),
            solution,
            real,
            solves: self.solves,
            finished: Now::read(),
            took: started.elapsed(),
        })
    }
}
