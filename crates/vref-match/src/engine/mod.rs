//! The matcher's engine: state kept by track id across snapshots, so that
//! a snapshot that changes k objects recomputes only their rows and
//! columns of the appearance affinity, the distance matrices and the
//! spatial kernel values, and (live tier) the next solve starts from the
//! last solution.

mod background;
mod dots;
mod resume;
mod view;

use std::collections::HashMap;

use vref_scene::{SceneGraph, Side};

use resume::Resumer;
pub use view::Change;
use view::View;

use crate::{
    MatchError, Method, PairAffinity, Params, Problem, Solution, SolveOptions, SpatialAffinity,
    SpatialTerm, Tier, candidate_pairs, solve_with,
};

/// The last solve, with the track ids its rows and columns stood for.
#[derive(Debug, Clone)]
struct Solved {
    human_ids: Vec<u64>,
    robot_ids: Vec<u64>,
    solution: Solution,
}

/// Incremental matching of two views that change over time.
#[derive(Debug, Clone)]
pub struct Engine {
    method: Method,
    tier: Tier,
    params: Params,
    human: View,
    robot: View,
    /// `n x m` cosine affinities of the current objects (ALGORITHMS.md
    /// Eq. 1); 1 where either view has no features.
    appearance: Vec<f64>,
    /// The spatial term of the last solve and, for each current object,
    /// its index in that term if unchanged since.
    spatial: Option<SpatialTerm>,
    human_in_spatial: Vec<Option<usize>>,
    robot_in_spatial: Vec<Option<usize>>,
    solved: Option<Solved>,
    /// The appearance affinity the live tier's current candidate pairs were
    /// chosen from: while it is unchanged (objects only moved), so are they.
    candidates_from: Vec<f64>,
    /// Whether the views changed since the last solve.
    dirty: bool,
    /// `rigid`, live tier: what one solve carries to the next.
    rigid: Resumer,
}

impl Engine {
    pub fn new(method: Method, tier: Tier, params: Params) -> Result<Self, MatchError> {
        params.validate()?;
        Ok(Self {
            method,
            tier,
            params,
            human: View::default(),
            robot: View::default(),
            appearance: Vec::new(),
            spatial: None,
            human_in_spatial: Vec::new(),
            robot_in_spatial: Vec::new(),
            solved: None,
            candidates_from: Vec::new(),
            dirty: true,
            rigid: Resumer::default(),
        })
    }

    pub fn method(&self) -> Method {
        self.method
    }

    pub fn tier(&self) -> Tier {
        self.tier
    }

    /// Takes `side`'s new snapshot. Graphs with an edge list are refused:
    /// snapshots from the feeds are fully connected.
    pub fn update(&mut self, side: Side, graph: &SceneGraph) -> Result<Change, MatchError> {
        if graph.edges().is_some() {
            return Err(MatchError::EdgeListInEngine);
        }
        let other = match side {
            Side::Human => &self.robot,
            Side::Robot => &self.human,
        };
        let (mine, theirs) = (
            graph.feature_dim(),
            other.objects.first().map_or(0, |o| o.feature.len()),
        );
        if mine != 0 && theirs != 0 && mine != theirs {
            let (human, robot) = match side {
                Side::Human => (mine, theirs),
                Side::Robot => (theirs, mine),
            };
            return Err(MatchError::FeatureDimsDiffer { human, robot });
        }
        let had_features = (self.human.has_features(), self.robot.has_features());
        let view = match side {
            Side::Human => &mut self.human,
            Side::Robot => &mut self.robot,
        };
        // A view whose up vector changed asks for a new solve, though no
        // object did.
        let turned = view.up != graph.up();
        view.up = graph.up();
        let (old_n, old_m) = (self.human.len(), self.robot.len());
        let (unchanged, change) = match side {
            Side::Human => self.human.update(graph),
            Side::Robot => self.robot.update(graph),
        };
        let features_switched =
            had_features != (self.human.has_features(), self.robot.has_features());
        let identity = |count: usize| (0..count).map(Some).collect::<Vec<_>>();
        let (human_old, robot_old) = match side {
            Side::Human => (unchanged, identity(self.robot.len())),
            Side::Robot => (identity(self.human.len()), unchanged),
        };
        self.update_appearance(&human_old, &robot_old, old_m, features_switched);
        let compose = |since: &[Option<usize>], old: &[Option<usize>], had: usize| {
            old.iter()
                .map(|o| o.and_then(|k| if since.len() == had { since[k] } else { None }))
                .collect::<Vec<_>>()
        };
        self.human_in_spatial = compose(&self.human_in_spatial, &human_old, old_n);
        self.robot_in_spatial = compose(&self.robot_in_spatial, &robot_old, old_m);
        self.dirty |= change.any() || turned || self.solved.is_none();
        Ok(change)
    }

    /// Recomputes the appearance entries of changed objects and copies the
    /// others (`*_old[k]`: the object's index before, if unchanged).
    fn update_appearance(
        &mut self,
        human_old: &[Option<usize>],
        robot_old: &[Option<usize>],
        old_m: usize,
        recompute_all: bool,
    ) {
        let (n, m) = (self.human.len(), self.robot.len());
        let no_features = !(self.human.has_features() && self.robot.has_features());
        let mut appearance = vec![0.0; n * m];
        // The robot features by dimension only where some pair is new: an
        // update that moved nothing copies every entry.
        let any_new = recompute_all
            || human_old.iter().any(Option::is_none)
            || robot_old.iter().any(Option::is_none);
        let columns = if no_features || !any_new {
            None
        } else {
            dots::Columns::of(&self.robot.objects)
        };
        let mut row = Vec::new();
        for (i, h) in self.human.objects.iter().enumerate() {
            let kept = |a: usize| human_old[i].is_some() && robot_old[a].is_some();
            let dots = columns
                .as_ref()
                .filter(|_| recompute_all || (0..m).any(|a| !kept(a)))
                .and_then(|c| c.dots(&h.feature, &mut row));
            for (a, r) in self.robot.objects.iter().enumerate() {
                appearance[i * m + a] = match (human_old[i], robot_old[a]) {
                    (Some(oi), Some(oa)) if !recompute_all => self.appearance[oi * old_m + oa],
                    _ if no_features || h.norm == 0.0 || r.norm == 0.0 => 1.0,
                    _ => {
                        let dot = dots.map_or_else(
                            || crate::appearance::dot(&h.feature, &r.feature),
                            |d| d[a],
                        );
                        dot / (h.norm * r.norm)
                    }
                };
            }
        }
        self.appearance = appearance;
    }

    /// The last solve's solution, without solving.
    pub fn solution(&self) -> Option<&Solution> {
        self.solved.as_ref().map(|s| &s.solution)
    }

    /// Whether the last solve started from the motions the solve before it
    /// kept instead of a full search (`rigid` in the live tier only).
    pub fn resumed(&self) -> bool {
        self.rigid.last_resumed
    }

    /// Full searches of `rigid` in the live tier so far, on the solve's
    /// own thread or apart (`rigid_full_apart`), counting a search apart
    /// once a solve has taken up its motions.
    pub fn full_searches(&self) -> u64 {
        self.rigid.full_searches
    }

    /// Has `begin` run first on the thread of every full search apart
    /// (`rigid_full_apart`): a service lowers that thread's priority
    /// there, since only a later solve needs its result.
    pub fn on_search_thread(&mut self, begin: fn()) {
        self.rigid.begin = Some(begin);
    }

    /// Waits for `rigid`'s full search running apart, if one is, and takes
    /// up its motions for the next solve: what a solve does by itself once
    /// the search has ended. For tools and tests that want the same
    /// answers whatever the machine's speed.
    pub fn settle(&mut self) {
        self.rigid.take_up(true);
    }

    /// Whether a solve would give something new: the views changed, or a
    /// full search of `rigid` apart has ended whose motions a solve would
    /// take up.
    pub fn is_dirty(&self) -> bool {
        self.dirty || self.solved.is_none() || self.rigid.has_news()
    }

    /// Solves if the views changed since the last solve, and returns the
    /// solution with the track ids of its rows and columns.
    pub fn solve(&mut self) -> Result<(&Solution, &[u64], &[u64]), MatchError> {
        if self.is_dirty() {
            self.resolve()?;
        }
        match &self.solved {
            Some(s) => Ok((&s.solution, &s.human_ids, &s.robot_ids)),
            None => Err(MatchError::EmptyGraph { side: "human" }),
        }
    }

    fn resolve(&mut self) -> Result<(), MatchError> {
        let (n, m) = (self.human.len(), self.robot.len());
        if n == 0 {
            return Err(MatchError::EmptyGraph { side: "human" });
        }
        if m == 0 {
            return Err(MatchError::EmptyGraph { side: "robot" });
        }
        // `rigid` and `clipper` never multiply by S and have no iterations
        // to stop early or warm-start: the live tier's shortcuts would only
        // prune their candidates, so they solve the exact tier's problem
        // (`rigid`'s own live shortcut is in `resume`).
        let tier = if matches!(self.method, Method::Rigid | Method::Clipper) {
            Tier::Exact
        } else {
            self.tier
        };
        let mut problem = match tier {
            Tier::Exact => Problem {
                n,
                m,
                appearance: self.appearance.clone(),
                spatial: SpatialTerm::Edges(self.exact_spatial()),
                human_positions: Vec::new(),
                robot_positions: Vec::new(),
                human_sigmas: Vec::new(),
                robot_sigmas: Vec::new(),
                human_up: None,
                robot_up: None,
            },
            Tier::Live => Problem::pruned(n, m, self.appearance.clone(), self.live_spatial()),
        };
        // `rigid` works on positions (both tiers).
        let points =
            |objects: &[view::Tracked]| objects.iter().map(|o| o.position.into()).collect();
        problem.human_positions = points(&self.human.objects);
        problem.robot_positions = points(&self.robot.objects);
        let sigmas = |objects: &[view::Tracked]| objects.iter().map(|o| o.sigma).collect();
        problem.human_sigmas = sigmas(&self.human.objects);
        problem.robot_sigmas = sigmas(&self.robot.objects);
        problem.human_up = self.human.up;
        problem.robot_up = self.robot.up;
        let warm = match tier {
            Tier::Exact => None,
            Tier::Live => self.warm_start(),
        };
        let options = SolveOptions {
            warm_start: warm.as_deref(),
            stop_when_stable: (tier == Tier::Live).then_some(self.params.live.stable_iterations),
        };
        let params = match self.tier {
            Tier::Exact => self.params,
            Tier::Live => self.params.for_live(),
        };
        let ids = |objects: &[view::Tracked]| objects.iter().map(|o| o.id).collect::<Vec<_>>();
        let (human_ids, robot_ids) = (ids(&self.human.objects), ids(&self.robot.objects));
        let solution = if self.method == Method::Rigid && self.tier == Tier::Live {
            self.rigid.solve(&problem, &params, &human_ids, &robot_ids)
        } else {
            solve_with(self.method, &problem, &params, options)?
        };
        self.spatial = Some(problem.spatial);
        self.human_in_spatial = (0..n).map(Some).collect();
        self.robot_in_spatial = (0..m).map(Some).collect();
        self.solved = Some(Solved {
            human_ids,
            robot_ids,
            solution,
        });
        self.dirty = false;
        Ok(())
    }

    /// The exact tier's S, reusing the kernel values of unchanged objects.
    fn exact_spatial(&mut self) -> SpatialAffinity {
        let previous = self.spatial.take();
        let (h, r) = (&self.human, &self.robot);
        match previous {
            Some(SpatialTerm::Edges(previous))
                if !matches!(
                    self.method,
                    Method::Appearance | Method::Rigid | Method::Clipper
                ) =>
            {
                SpatialAffinity::updated(
                    previous,
                    &self.human_in_spatial,
                    &self.robot_in_spatial,
                    &h.distances,
                    &r.distances,
                )
            }
            _ => SpatialAffinity::from_distances(
                h.len(),
                r.len(),
                &h.distances,
                &r.distances,
                self.params.beta,
            ),
        }
    }

    /// The live tier's S on today's candidate pairs, reusing the kernel
    /// values of unchanged objects.
    fn live_spatial(&mut self) -> PairAffinity {
        let (h, r) = (&self.human, &self.robot);
        let (n, m) = (h.len(), r.len());
        let previous = self.spatial.take();
        let pairs = match &previous {
            Some(SpatialTerm::Pairs(p))
                if p.shape() == (n, m) && self.candidates_from == self.appearance =>
            {
                p.pairs().to_vec()
            }
            _ => {
                self.candidates_from.clone_from(&self.appearance);
                candidate_pairs(&self.appearance, n, m, &self.params.live)
            }
        };
        match previous {
            Some(SpatialTerm::Pairs(previous)) => PairAffinity::updated(
                previous,
                &self.human_in_spatial,
                &self.robot_in_spatial,
                n,
                m,
                pairs,
                &h.distances,
                &r.distances,
                self.params.beta,
            ),
            _ => PairAffinity::new(n, m, pairs, &h.distances, &r.distances, self.params.beta),
        }
    }

    /// The last soft answer carried over by track id; pairs it did not
    /// have start at its mean.
    fn warm_start(&self) -> Option<Vec<f64>> {
        let last = self.solved.as_ref()?;
        let lm = last.robot_ids.len();
        let (rows, cols) = (index_by_id(&last.human_ids), index_by_id(&last.robot_ids));
        let soft = &last.solution.soft;
        let mean = soft.iter().sum::<f64>() / soft.len().max(1) as f64;
        // One lookup per object, not per pair: n x m hashed lookups were
        // a tenth of an incremental live solve at 32 objects.
        let columns: Vec<Option<usize>> = self
            .robot
            .objects
            .iter()
            .map(|r| cols.get(&r.id).copied())
            .collect();
        let mut warm = Vec::with_capacity(self.human.len() * self.robot.len());
        for h in &self.human.objects {
            match rows.get(&h.id) {
                Some(&i) => {
                    let last_row = &soft[i * lm..(i + 1) * lm];
                    warm.extend(columns.iter().map(|c| c.map_or(mean, |a| last_row[a])));
                }
                None => warm.extend(std::iter::repeat_n(mean, columns.len())),
            }
        }
        Some(warm)
    }
}

/// Where each track id stands in `ids`.
pub(super) fn index_by_id(ids: &[u64]) -> HashMap<u64, usize> {
    ids.iter().enumerate().map(|(k, &id)| (id, k)).collect()
}
