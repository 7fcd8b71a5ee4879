//! RANSAC over candidate pairs for the motion between the two views, and
//! its rivals.

use nalgebra::Point3;

use super::RigidParams;
use super::costs::{Costs, RowScratch};
use super::side::Side;
use crate::Problem;
use crate::RigidMotion;

/// A motion with its score and the pairs its greedy assignment took
/// (kept so that no motion's pairs are computed twice under one costs).
type Scored = (f64, RigidMotion, Vec<(usize, usize)>);

/// Minimal samples tried per hypothesis scored; most fail the cheap
/// distance check, so this bounds the search when nothing is consistent.
const ATTEMPTS_PER_HYPOTHESIS: usize = 50;
/// Robot objects whose appearance affinity is this much below the row's
/// best are still candidates (a tenth of the likelihood at the
/// temperature this was chosen with, 0.1); in affinity units, so that the
/// temperature weighs appearance without widening the search.
const CANDIDATE_GAP: f64 = 0.1 * std::f64::consts::LN_10;
/// Re-fits per locally optimised hypothesis (each must raise its score).
const LOCAL_REFITS: usize = 3;

/// The best-scoring proper motion among hypotheses fitted to three
/// distance-consistent candidate pairs; `None` when either view has fewer
/// than three objects or no sample is consistent.
pub(super) fn search(
    costs: &Costs<'_>,
    sigma: f64,
    rp: &RigidParams,
    seeds: &[RigidMotion],
) -> Option<Found> {
    let problem = costs.problem;
    let (n, m) = (problem.n, problem.m);
    if n < 3 || m < 3 {
        return None;
    }
    let hp = &problem.human_positions;
    let rpos = &problem.robot_positions;
    // The samples are drawn over objects in an order of their positions,
    // not of the lists they came in, so that relabelling a view draws the
    // same hypotheses and gives the same answer.
    let human_order = position_order(hp);
    let robot_rank = ranks(&position_order(rpos));
    let candidates = candidate_columns(costs.log_g, n, m, rp, &robot_rank);
    // Distances may disagree by the noise of two positions on each side.
    let tolerance = 3.0 * sigma;
    let mut rng = SplitMix(rp.seed ^ ((n as u64) << 32) ^ m as u64);
    // Every sample checks its pairs' distances: computed once.
    let (human_d, robot_d) = (distances(hp), distances(rpos));
    let heights = heights(problem);
    let size = sample_size(&heights);
    let hypotheses = if heights.is_some() {
        rp.hypotheses_upright
    } else {
        rp.hypotheses
    };
    let mut top: Vec<Scored> = Vec::new();
    let max_attempts = hypotheses.saturating_mul(ATTEMPTS_PER_HYPOTHESIS);
    let mut consistent: Vec<usize> = Vec::with_capacity(m);
    let mut scratch = Scratch::default();
    let side = Side::of(problem);
    let probes = probe_points(hp);
    let same = |a: &RigidMotion, b: &RigidMotion| same_motion(a, b, &probes, 2.0 * sigma);
    // A motion that explains nearly every object nearly perfectly leaves
    // nothing for further hypotheses to find.
    let decisive = rp.decisive_share * largest_score(n, m, rp);
    let decisive_after = rp.decisive_after.saturating_mul(64).div_ceil(n * m);
    // Sample edges shorter than the tolerance give poorly determined
    // rotations and are avoided, unless a sparse scene has too few samples
    // without them to fill the kept few.
    let keep = rp.local_optimisations.max(1);
    let mut settled = false;
    // Hypotheses scored in the rounds kept: the tests a coincidence had.
    let mut tests = 0;
    // Rounds of (distance tolerance, shortest edge, shortcut). Under the
    // depth-error model the tolerance must admit errors along the rays that
    // are large against the spacing, which leaves guided sampling little to
    // go on. Where that error is assumed (`depth_error`: nothing stated), a
    // first round at the lateral scale alone settles scenes whose positions
    // are better than assumed at once; it is a shortcut only: unless it
    // settles the scene it is forgotten (its own generator, its motions
    // dropped), so it never changes the answer to a scene it does not
    // settle. Errors the sensors state are taken at their word: no
    // shortcut, whose search would be wasted on noisy scenes.
    let mut rounds = Vec::with_capacity(3);
    if let Some(rays) = costs.rays.as_ref().filter(|r| r.assumed) {
        let precise = 3.0 * rays.lateral.sqrt();
        rounds.push((precise, precise, true));
    }
    rounds.extend([(tolerance, tolerance, false), (tolerance, 0.0, false)]);
    let mut shortcut_rng = SplitMix(!rng.0);
    for (tolerance, min_edge, shortcut) in rounds {
        // Without a decisive motion the short edges get their turn too: in
        // a scene of a few objects the right triangle may have no edge
        // longer than the tolerance, while wrong ones fill the kept few.
        let short = min_edge == 0.0;
        if settled || (short && !rp.short_edges_always && top.len() >= keep) {
            break;
        }
        let rng = if shortcut {
            &mut shortcut_rng
        } else {
            &mut rng
        };
        let edges = Edges {
            human: &human_d,
            robot: &robot_d,
            n,
            m,
            tolerance,
            min_edge,
            heights: heights.as_ref().map(|(h, r)| (h.as_slice(), r.as_slice())),
        };
        let mut scored = 0;
        let mut attempts = 0;
        let mut drawn = Vec::new();
        while scored < hypotheses && attempts < max_attempts {
            attempts += 1;
            let Some(s) = draw_sample(
                rng,
                &human_order,
                &candidates,
                &edges,
                size,
                &mut consistent,
            ) else {
                continue;
            };
            let from = s.map(|(i, _)| hp[i]);
            let to = s.map(|(_, j)| rpos[j]);
            let Some(motion) = problem.fit_motion(&from[..size], &to[..size], &[1.0; 3][..size])
            else {
                continue;
            };
            if rp.same_side && !side.allows(&motion) {
                continue;
            }
            scored += 1;
            let score = if shortcut && scored > decisive_after {
                // The shortcut round's kept motions matter only where it
                // settles the scene, so once a decisive hypothesis would
                // settle it, one is scored only as far as it could still
                // be decisive.
                drawn.push(motion);
                greedy(costs, &motion, rp.unmatched_cost, decisive, &mut scratch).map(|(s, _)| s)
            } else {
                admit(&mut top, keep, costs, rp, motion, &mut scratch, same)
            };
            if score.is_some_and(|s| s >= decisive) && scored >= decisive_after {
                // It settles: the kept few are the ones scoring every
                // hypothesis of the round in turn keeps.
                for &motion in &drawn {
                    admit(&mut top, keep, costs, rp, motion, &mut scratch, same);
                }
                settled = true;
                break;
            }
        }
        if shortcut && !settled {
            top.clear();
        } else {
            tests += scored;
        }
    }
    // Motions found otherwise (the consistency graph's cluster) compete
    // with the sampled ones on the same score.
    for seed in seeds {
        if let Some((score, pairs)) = greedy(
            costs,
            seed,
            rp.unmatched_cost,
            f64::NEG_INFINITY,
            &mut scratch,
        ) {
            keep_best(&mut top, keep, (score, *seed, pairs), same);
        }
    }
    let refined = optimise_locally(costs, rp, top, &mut scratch);
    found(rp, refined, same, tests).map(|f| Found { settled, ..f })
}

/// Scores `motion` and keeps it in `top` (the `keep` best distinct motions
/// so far) if it enters: scored fully only while it can. Its score, or
/// `None` when it was cut short, below any score that would settle the
/// search.
fn admit(
    top: &mut Vec<Scored>,
    keep: usize,
    costs: &Costs<'_>,
    rp: &RigidParams,
    motion: RigidMotion,
    scratch: &mut Scratch,
    same: impl Fn(&RigidMotion, &RigidMotion) -> bool,
) -> Option<f64> {
    let mut beat = if top.len() < keep {
        f64::NEG_INFINITY
    } else {
        top.last().map_or(f64::NEG_INFINITY, |(s, _, _)| *s)
    };
    // A motion naming the pairs of one held enters only in its place, by
    // beating it (`keep_best`); more than half the hypotheses of a large
    // scene are such. Cut short below the held one's score, or below
    // `decisive` where that is less, it changes nothing.
    if let Some((held, _, _)) = top.iter().find(|(_, held, _)| same(held, &motion))
        && copies_cut()
    {
        let decisive = rp.decisive_share * largest_score(costs.problem.n, costs.problem.m, rp);
        beat = beat.max(held.min(decisive));
    }
    let Some((score, pairs)) = greedy(costs, &motion, rp.unmatched_cost, beat, scratch) else {
        #[cfg(test)]
        CUT_SHORT.with(|c| c.set(c.get() + 1));
        return None;
    };
    keep_best(top, keep, (score, motion, pairs), same);
    Some(score)
}

/// Whether near-copies of kept motions are cut short ([`admit`]); the
/// tests turn it off to compare.
#[cfg(not(test))]
fn copies_cut() -> bool {
    true
}

#[cfg(test)]
thread_local! {
    static COPIES_CUT: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
    /// Hypotheses [`admit`] cut short.
    static CUT_SHORT: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

#[cfg(test)]
fn copies_cut() -> bool {
    COPIES_CUT.with(std::cell::Cell::get)
}

/// What a motion drawn by the sampler scores by chance in this scene: the
/// scores of up to `samples` drawn hypotheses after the same local
/// optimisation the best motion had. Hypotheses that are the best motion
/// again are left out: in a scene with a right motion they are not
/// chance, and in one without they are few. Most drawn hypotheses are
/// wrong, so the scores sample the null the best motion is tested against.
pub(super) fn chance_inliers(
    costs: &Costs<'_>,
    rp: &RigidParams,
    samples: usize,
    best: Option<&RigidMotion>,
) -> Vec<f64> {
    let problem = costs.problem;
    let (n, m) = (problem.n, problem.m);
    if n < 3 || m < 3 {
        return Vec::new();
    }
    let hp = &problem.human_positions;
    let rpos = &problem.robot_positions;
    let human_order = position_order(hp);
    let robot_rank = ranks(&position_order(rpos));
    let candidates = candidate_columns(costs.log_g, n, m, rp, &robot_rank);
    let tolerance = 3.0 * costs.typical;
    let (human_d, robot_d) = (distances(hp), distances(rpos));
    let heights = heights(problem);
    let edges = Edges {
        human: &human_d,
        robot: &robot_d,
        n,
        m,
        tolerance,
        min_edge: f64::NEG_INFINITY,
        heights: heights.as_ref().map(|(h, r)| (h.as_slice(), r.as_slice())),
    };
    let probes = probe_points(hp);
    let side = Side::of(problem);
    let mut rng = SplitMix(rp.seed.rotate_left(17) ^ ((n as u64) << 32) ^ m as u64);
    let mut consistent = Vec::with_capacity(m);
    let mut scratch = Scratch::default();
    let mut counts = Vec::with_capacity(samples);
    let mut drawn = 0;
    for _ in 0..samples.saturating_mul(ATTEMPTS_PER_HYPOTHESIS) {
        if drawn >= samples {
            break;
        }
        let size = sample_size(&heights);
        let Some(s) = draw_sample(
            &mut rng,
            &human_order,
            &candidates,
            &edges,
            size,
            &mut consistent,
        ) else {
            continue;
        };
        let from = s.map(|(i, _)| hp[i]);
        let to = s.map(|(_, j)| rpos[j]);
        let Some(motion) = problem.fit_motion(&from[..size], &to[..size], &[1.0; 3][..size]) else {
            continue;
        };
        if rp.same_side && !side.allows(&motion) {
            continue;
        }
        drawn += 1;
        let Some((score, pairs)) = greedy(
            costs,
            &motion,
            rp.unmatched_cost,
            f64::NEG_INFINITY,
            &mut scratch,
        ) else {
            continue;
        };
        let refined = optimise_locally(costs, rp, vec![(score, motion, pairs)], &mut scratch);
        // The local optimisation's score is the greedy pass's own, to the
        // bit: no second pass.
        let Some(&(score, motion, _)) = refined.first() else {
            continue;
        };
        if best.is_some_and(|b| same_motion(&motion, b, &probes, 2.0 * costs.typical)) {
            continue;
        }
        counts.push(score);
    }
    counts
}

/// The search's kept motions judged again under `costs` (the same scene
/// with other noise scales): each re-fitted to what it explains there, the
/// best chosen, its rivals weighed. `tests` is the search's count.
pub(super) fn rescore(
    costs: &Costs<'_>,
    rp: &RigidParams,
    motions: &[RigidMotion],
    tests: usize,
) -> Option<Found> {
    let mut scratch = Scratch::default();
    let top = motions
        .iter()
        .filter_map(|m| {
            greedy(costs, m, rp.unmatched_cost, f64::NEG_INFINITY, &mut scratch)
                .map(|(score, pairs)| (score, *m, pairs))
        })
        .collect();
    let refined = optimise_locally(costs, rp, top, &mut scratch);
    let probes = probe_points(&costs.problem.human_positions);
    let tolerance = 2.0 * costs.typical;
    let same = |a: &RigidMotion, b: &RigidMotion| same_motion(a, b, &probes, tolerance);
    found(rp, refined, same, tests)
}

fn found(
    rp: &RigidParams,
    refined: Vec<Scored>,
    same: impl Fn(&RigidMotion, &RigidMotion) -> bool,
    tests: usize,
) -> Option<Found> {
    let &(score, motion, _) = refined.first()?;
    let alternatives = rivals(rp, &refined, same);
    Some(Found {
        motion,
        score,
        alternatives,
        kept: refined.into_iter().map(|(_, m, _)| m).collect(),
        tests,
        settled: false,
    })
}

/// The largest score a motion can reach: every object of the smaller view
/// explained at no cost, each gaining what "no partner" would cost.
pub(super) fn largest_score(n: usize, m: usize, rp: &RigidParams) -> f64 {
    rp.unmatched_cost * n.min(m) as f64
}

/// The search's score of `motion` (its greedy gain over "no partner").
pub(super) fn score_of(costs: &Costs<'_>, rp: &RigidParams, motion: &RigidMotion) -> f64 {
    greedy(
        costs,
        motion,
        rp.unmatched_cost,
        f64::NEG_INFINITY,
        &mut Scratch::default(),
    )
    .map_or(0.0, |(s, _)| s)
}

/// The pairs `motion` explains, by the search's greedy assignment.
pub(super) fn explained(
    costs: &Costs<'_>,
    rp: &RigidParams,
    motion: &RigidMotion,
) -> Vec<(usize, usize)> {
    greedy(
        costs,
        motion,
        rp.unmatched_cost,
        f64::NEG_INFINITY,
        &mut Scratch::default(),
    )
    .map(|(_, p)| p)
    .unwrap_or_default()
}

/// Which two pairs may share a sample: the human objects' distance must
/// be usable as an edge, and the robot objects' must agree with it.
struct Edges<'a> {
    /// Row-major distances between the human objects, and the robot's.
    human: &'a [f64],
    robot: &'a [f64],
    n: usize,
    m: usize,
    /// How far two distances may disagree.
    tolerance: f64,
    /// Human edges this short or shorter are not used.
    min_edge: f64,
    /// Each object's height along its view's up vector (human, robot),
    /// where both views know it: a pair of pairs must agree in the rise
    /// between them too, which no turn about up changes.
    heights: Option<(&'a [f64], &'a [f64])>,
}

impl Edges<'_> {
    /// The distance between human objects `i` and `j` where it may be a
    /// sample's edge.
    fn human_edge(&self, i: usize, j: usize) -> Option<f64> {
        let d = self.human[i * self.n + j];
        // Where up is known a sample's edge fixes the turn about it only
        // by its level part: an edge along up fixes none.
        let level = self.heights.map_or(d, |(h, _)| {
            let rise = h[j] - h[i];
            (d * d - rise * rise).max(0.0).sqrt()
        });
        (i != j && level > self.min_edge).then_some(d)
    }

    /// Whether robot objects `a` and `b` are distinct and as far apart as
    /// a human edge of length `d`.
    fn agrees(&self, d: f64, a: usize, b: usize) -> bool {
        a != b && (d - self.robot[a * self.m + b]).abs() <= self.tolerance
    }

    /// Whether human objects `i` to `j` rise as much as robot objects `a`
    /// to `b` (always, where the heights are unknown).
    fn level(&self, i: usize, j: usize, a: usize, b: usize) -> bool {
        self.heights
            .is_none_or(|(h, r)| ((h[j] - h[i]) - (r[b] - r[a])).abs() <= self.tolerance)
    }
}

/// Each object's height along its view's up vector, where both views
/// know theirs.
fn heights(problem: &Problem) -> Option<(Vec<f64>, Vec<f64>)> {
    let (up_h, up_r) = problem.gravity()?;
    let along = |points: &[nalgebra::Point3<f64>], up: &nalgebra::Vector3<f64>| {
        points.iter().map(|p| p.coords.dot(up)).collect()
    };
    Some((
        along(&problem.human_positions, &up_h),
        along(&problem.robot_positions, &up_r),
    ))
}

/// Candidate pairs a hypothesis is fitted to: three fix a motion, two
/// where both up vectors are known (a turn about up and a translation).
fn sample_size(heights: &Option<(Vec<f64>, Vec<f64>)>) -> usize {
    if heights.is_some() { 2 } else { 3 }
}

/// One sample of `size` (2 or 3) candidate pairs, in the first `size`
/// entries, by guided sampling: each pair after the first is drawn only
/// among the candidates whose distances agree with the pairs drawn before
/// (`edges`), so that a right first pair is likely to grow into a right
/// sample even when a row has many look-alike candidates. `None` when a
/// row has no consistent candidate.
fn draw_sample(
    rng: &mut SplitMix,
    human_order: &[usize],
    candidates: &[Vec<usize>],
    edges: &Edges<'_>,
    size: usize,
    consistent: &mut Vec<usize>,
) -> Option<[(usize, usize); 3]> {
    let n = human_order.len();
    let i = human_order[rng.below(n)];
    let first = (i, candidates[i][rng.below(candidates[i].len())]);
    let mut s = [first; 3];
    for k in 1..size.min(3) {
        let row = human_order[rng.below(n)];
        // The human edges to the pairs drawn before are the row's, not each
        // candidate's: checked once (most samples fail here in scenes
        // whose tolerance is wide against their extent).
        let mut before = [(0.0, 0, 0); 2];
        for (b, &(i, a)) in before.iter_mut().zip(&s[..k]) {
            *b = (edges.human_edge(i, row)?, i, a);
        }
        consistent.clear();
        consistent.extend(candidates[row].iter().copied().filter(|&col| {
            before[..k]
                .iter()
                .all(|&(d, i, a)| edges.agrees(d, a, col) && edges.level(i, row, a, col))
        }));
        if consistent.is_empty() {
            return None;
        }
        s[k] = (row, consistent[rng.below(consistent.len())]);
    }
    Some(s)
}

/// Local optimisation: a motion fitted to three noisy pairs is only
/// roughly right, so the best few are re-fitted to the pairs they explain
/// before they are compared. Returns them best first.
fn optimise_locally(
    costs: &Costs<'_>,
    rp: &RigidParams,
    top: Vec<Scored>,
    scratch: &mut Scratch,
) -> Vec<Scored> {
    let mut refined: Vec<Scored> = Vec::with_capacity(top.len());
    for (mut score, mut motion, mut pairs) in top {
        for _ in 0..LOCAL_REFITS {
            let Some(refit) = fit_pairs(costs.problem, &pairs) else {
                break;
            };
            // A greedy pass that is not cut short by `beat` takes the same
            // pairs as one without it.
            let Some((refit_score, refit_pairs)) =
                greedy(costs, &refit, rp.unmatched_cost, score, scratch)
            else {
                break;
            };
            if refit_score <= score {
                break;
            }
            (score, motion, pairs) = (refit_score, refit, refit_pairs);
        }
        refined.push((score, motion, pairs));
    }
    refined.sort_by(|a, b| b.0.total_cmp(&a.0));
    refined
}

/// The best few of `refined` (after the best, `motion`) that pair objects
/// otherwise than it and than each other, at most `rivals`: a motion that
/// the local optimisation left short of the same pairs' fit is the best
/// motion again, only fitted worse, and would dispute nothing real.
fn rivals(
    rp: &RigidParams,
    refined: &[Scored],
    same: impl Fn(&RigidMotion, &RigidMotion) -> bool,
) -> Vec<(f64, RigidMotion)> {
    let sorted = |p: &[(usize, usize)]| {
        let mut p = p.to_vec();
        p.sort_unstable();
        p
    };
    let Some((_, motion, best_pairs)) = refined.first() else {
        return Vec::new();
    };
    let mut seen = vec![sorted(best_pairs)];
    let mut alternatives = Vec::new();
    for &(other_score, other, ref other_pairs) in refined.iter().skip(1) {
        if alternatives.len() >= rp.rivals {
            break;
        }
        if same(motion, &other) {
            continue;
        }
        let pairs = sorted(other_pairs);
        if !seen.contains(&pairs) {
            seen.push(pairs);
            alternatives.push((other_score, other));
        }
    }
    alternatives
}

/// The search's answer: the best motion, its score, and the best few
/// motions that pair objects otherwise (each differently from the others),
/// with their scores, best first.
pub(super) struct Found {
    pub(super) motion: RigidMotion,
    pub(super) score: f64,
    pub(super) alternatives: Vec<(f64, RigidMotion)>,
    /// Every motion the search kept, best first.
    pub(super) kept: Vec<RigidMotion>,
    /// Hypotheses the search scored (the shortcut round's only when it
    /// settled the scene).
    pub(super) tests: usize,
    /// Whether a decisive motion ended the search (explaining nearly every
    /// object nearly perfectly after enough hypotheses for the scene's
    /// size): chance does not reach that, and is not measured.
    pub(super) settled: bool,
}

/// Inserts `(score, motion)` into `top`, which holds the `k` best
/// distinct motions so far, best first: a motion that places the probe
/// points like one already held replaces it only when it scores higher.
fn keep_best(
    top: &mut Vec<Scored>,
    k: usize,
    scored: Scored,
    same: impl Fn(&RigidMotion, &RigidMotion) -> bool,
) {
    let (score, motion) = (scored.0, scored.1);
    if let Some(at) = top.iter().position(|(_, held, _)| same(held, &motion)) {
        if top[at].0 >= score {
            return;
        }
        top.remove(at);
    }
    let at = top.partition_point(|(s, _, _)| *s >= score);
    if at < k {
        top.insert(at, scored);
        top.truncate(k);
    }
}

/// Whether two motions place every probe point within `tolerance` of
/// each other (they name the same correspondences).
fn same_motion(a: &RigidMotion, b: &RigidMotion, probes: &[Point3<f64>], tolerance: f64) -> bool {
    probes
        .iter()
        .all(|p| (a.apply(p) - b.apply(p)).norm_squared() <= tolerance * tolerance)
}

/// How well `motion` explains the scene: each human object's best pair
/// under it, taken greedily by gain over "no partner" with every robot
/// object used once (a cheap stand-in for the assignment). Returns the
/// total gain and the pairs taken, or `None` as soon as the total cannot
/// reach `beat` (each row gains at most `unmatched`). Objects without a
/// partner add nothing instead of dragging a right motion down.
fn greedy(
    costs: &Costs<'_>,
    motion: &RigidMotion,
    unmatched: f64,
    beat: f64,
    scratch: &mut Scratch,
) -> Option<(f64, Vec<(usize, usize)>)> {
    let problem = costs.problem;
    let (n, m) = (problem.n, problem.m);
    scratch.gains.clear();
    let mut bound = unmatched * n as f64;
    for i in 0..n {
        let [first, second] = costs.cheapest_two(i, motion, unmatched, &mut scratch.row);
        bound -= unmatched - (unmatched - first.0).max(0.0);
        if bound < beat {
            return None;
        }
        for (c, j) in [first, second] {
            if c < unmatched && j != usize::MAX {
                scratch.gains.push(gain_key(unmatched - c, i, j));
            }
        }
    }
    // Greatest gain first, ties by row and column: one integer sort.
    scratch.gains.sort_unstable();
    scratch.row_used.clear();
    scratch.row_used.resize(n, false);
    scratch.col_used.clear();
    scratch.col_used.resize(m, false);
    let mut total = 0.0;
    let mut pairs = Vec::with_capacity(n.min(m));
    for &key in &scratch.gains {
        let (gain, i, j) = from_gain_key(key);
        if !scratch.row_used[i] && !scratch.col_used[j] {
            scratch.row_used[i] = true;
            scratch.col_used[j] = true;
            total += gain;
            pairs.push((i, j));
        }
    }
    Some((total, pairs))
}

/// A pair's gain with its row `i` and column `j` as one integer that
/// orders the greatest gain first, ties by row, then column: a gain is
/// positive, so its bits order as it does; row and column below 2^32.
fn gain_key(gain: f64, i: usize, j: usize) -> u128 {
    (u128::from(!gain.to_bits()) << 64) | ((i as u128) << 32) | j as u128
}

/// The gain, row and column of a [`gain_key`].
fn from_gain_key(key: u128) -> (f64, usize, usize) {
    let gain = f64::from_bits(!((key >> 64) as u64));
    (gain, ((key >> 32) as u32) as usize, (key as u32) as usize)
}

/// Buffers reused by every [`greedy`] call of one search.
#[derive(Default)]
struct Scratch {
    row: RowScratch,
    gains: Vec<u128>,
    row_used: Vec<bool>,
    col_used: Vec<bool>,
}

/// The motion fitted to `pairs` of (human, robot) objects; `None` below
/// three pairs.
fn fit_pairs(problem: &Problem, pairs: &[(usize, usize)]) -> Option<RigidMotion> {
    if pairs.len() < 3 {
        return None;
    }
    let from: Vec<_> = pairs
        .iter()
        .map(|&(i, _)| problem.human_positions[i])
        .collect();
    let to: Vec<_> = pairs
        .iter()
        .map(|&(_, j)| problem.robot_positions[j])
        .collect();
    problem.fit_motion(&from, &to, &vec![1.0; pairs.len()])
}

/// For each human object, the robot objects that hypotheses may pair it
/// with, in the order of `robot_rank`: its `k` most similar (the lower
/// column first among equals), and every other whose appearance
/// likelihood is within [`CANDIDATE_GAP`] of the best in affinity (all of
/// them when appearance tells nothing, as without features).
fn candidate_columns(
    log_g: &[f64],
    n: usize,
    m: usize,
    rp: &RigidParams,
    robot_rank: &[usize],
) -> Vec<Vec<usize>> {
    let gap = candidate_gap(rp);
    (0..n)
        .map(|i| {
            let row = &log_g[i * m..(i + 1) * m];
            let mut order: Vec<usize> = (0..m).collect();
            // Those within the gap lead the row's order of similarity, so
            // the kept are its first `keep`: selected, not sorted (a search
            // asks this of every row).
            let within = row.iter().filter(|&&g| g >= gap).count();
            let keep = rp.candidates.max(within).clamp(1, m.max(1));
            if keep < m {
                order.select_nth_unstable_by(keep - 1, |&a, &b| {
                    row[b].total_cmp(&row[a]).then(a.cmp(&b))
                });
                order.truncate(keep);
            }
            order.sort_unstable_by_key(|&col| robot_rank[col]);
            order
        })
        .collect()
}

/// The log likelihood [`CANDIDATE_GAP`] below a row's best stands at:
/// the gap is of the likelihood before its floor (the floor keeps a
/// pair's cost bounded; it must not make every object a candidate).
fn candidate_gap(rp: &RigidParams) -> f64 {
    let floor = rp.appearance_floor;
    ((1.0 - floor) * (-CANDIDATE_GAP / rp.appearance_temperature).exp() + floor).ln()
}

/// Row-major distances between every two of `points`.
fn distances(points: &[Point3<f64>]) -> Vec<f64> {
    points
        .iter()
        .flat_map(|p| points.iter().map(move |q| (p - q).norm()))
        .collect()
}

/// Indices of `points` sorted by their coordinates, x first.
fn position_order(points: &[Point3<f64>]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        let (p, q) = (&points[a], &points[b]);
        p.x.total_cmp(&q.x)
            .then(p.y.total_cmp(&q.y))
            .then(p.z.total_cmp(&q.z))
            .then(a.cmp(&b))
    });
    order
}

/// `rank[k]`: where index `k` stands in `order`.
fn ranks(order: &[usize]) -> Vec<usize> {
    let mut rank = vec![0; order.len()];
    for (r, &k) in order.iter().enumerate() {
        rank[k] = r;
    }
    rank
}

/// The human view's extreme points along each axis and its centroid:
/// where two motions that pair objects differently disagree most.
fn probe_points(points: &[Point3<f64>]) -> Vec<Point3<f64>> {
    let mut probes = Vec::with_capacity(7);
    if points.is_empty() {
        return probes;
    }
    let centroid = points
        .iter()
        .fold(nalgebra::Vector3::zeros(), |c, p| c + p.coords)
        / points.len() as f64;
    probes.push(Point3::from(centroid));
    for axis in 0..3 {
        let by = |a: &&Point3<f64>, b: &&Point3<f64>| a[axis].total_cmp(&b[axis]);
        if let (Some(lo), Some(hi)) = (points.iter().min_by(by), points.iter().max_by(by)) {
            probes.push(*lo);
            probes.push(*hi);
        }
    }
    probes
}

/// A small deterministic generator (SplitMix64) for the sampler.
pub(super) struct SplitMix(pub(super) u64);

impl SplitMix {
    pub(super) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    pub(super) fn below(&mut self, bound: usize) -> usize {
        (self.next() % bound.max(1) as u64) as usize
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use nalgebra::Point3;

    use super::{
        COPIES_CUT, CUT_SHORT, Edges, SplitMix, candidate_columns, candidate_gap, distances,
        draw_sample, from_gain_key, gain_key,
    };

    fn cloud(rng: &mut SplitMix, k: usize) -> Vec<Point3<f64>> {
        let mut unit = || (rng.next() >> 11) as f64 / (1u64 << 53) as f64;
        (0..k)
            .map(|_| Point3::new(unit(), 0.5 * unit(), 0.2 * unit()))
            .collect()
    }

    /// Gain keys sort as the greedy takes them, greatest gain first, ties
    /// by row and then column, and give back their gain to the bit.
    #[test]
    fn gain_keys_order_the_greatest_gain_first() {
        let gains = [
            (4.5, 3, 1),
            (1e-300, 0, 0),
            (2.25, 7, 9),
            (2.25, 7, 2),
            (2.25, 1, 63),
            (f64::MIN_POSITIVE / 4.0, 2, 5),
            (0.1 + 0.2, 5, 5),
        ];
        let mut keys: Vec<u128> = gains.iter().map(|&(g, i, j)| gain_key(g, i, j)).collect();
        keys.sort_unstable();
        let sorted: Vec<(f64, usize, usize)> = keys.into_iter().map(from_gain_key).collect();
        let mut expected = gains.to_vec();
        expected.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        assert_eq!(sorted, expected);
    }

    /// The candidates selected are the first of the row sorted by
    /// similarity, as the definition says: its `k` most similar (the lower
    /// column first among equals) and every other within the gap, in the
    /// robot order; on rows with ties, with all or none within the gap.
    #[test]
    fn the_candidates_are_the_sorted_rows_first() {
        let rp = crate::RigidParams::default();
        let gap = candidate_gap(&rp);
        let mut rng = SplitMix(9);
        for (n, m, levels) in [(5, 3, 2), (7, 9, 3), (12, 40, 5), (9, 64, 1000), (4, 64, 1)] {
            // Affinities on a few levels about the gap: many ties, rows
            // with every column within the gap and rows with few.
            let log_g: Vec<f64> = (0..n * m)
                .map(|_| gap + 0.3 * (rng.below(levels) as f64 - 0.7 * levels as f64))
                .collect();
            let robot_rank: Vec<usize> = (0..m).map(|j| (j * 7 + 3) % m).collect();
            let got = candidate_columns(&log_g, n, m, &rp, &robot_rank);
            for (i, kept) in got.iter().enumerate() {
                let row = &log_g[i * m..(i + 1) * m];
                let mut order: Vec<usize> = (0..m).collect();
                order.sort_by(|&a, &b| row[b].total_cmp(&row[a]));
                let keep = order
                    .iter()
                    .enumerate()
                    .take_while(|&(rank, &j)| rank < rp.candidates || row[j] >= gap)
                    .count();
                order.truncate(keep.max(1));
                order.sort_by_key(|&col| robot_rank[col]);
                assert_eq!(kept, &order, "row {i} of {n} x {m}");
            }
        }
    }

    /// Every two pairs of a drawn sample use a human edge longer than the
    /// shortest allowed and robot objects as far apart within the
    /// tolerance; and a row without such a candidate ends the draw.
    #[test]
    fn a_sample_keeps_its_distances_and_its_edges() {
        let mut rng = SplitMix(5);
        let (n, m) = (12, 14);
        let (human, robot) = (cloud(&mut rng, n), cloud(&mut rng, m));
        let (human_d, robot_d) = (distances(&human), distances(&robot));
        let order: Vec<usize> = (0..n).collect();
        let candidates: Vec<Vec<usize>> = (0..n)
            .map(|i| (0..6).map(|k| (i + 3 * k) % m).collect())
            .collect();
        let (tolerance, min_edge) = (0.15, 0.2);
        let edges = Edges {
            human: &human_d,
            robot: &robot_d,
            n,
            m,
            tolerance,
            min_edge,
            heights: None,
        };
        let mut consistent = Vec::new();
        let (mut drawn, mut failed) = (0, 0);
        for _ in 0..2000 {
            let Some(s) = draw_sample(&mut rng, &order, &candidates, &edges, 3, &mut consistent)
            else {
                failed += 1;
                continue;
            };
            drawn += 1;
            for (x, &(i, a)) in s.iter().enumerate() {
                assert!(candidates[i].contains(&a), "{s:?}");
                for &(j, b) in &s[x + 1..] {
                    let (dh, dr) = (human_d[i * n + j], robot_d[a * m + b]);
                    assert!(i != j && a != b, "{s:?}");
                    assert!(dh > min_edge, "edge {dh} in {s:?}");
                    assert!((dh - dr).abs() <= tolerance, "{dh} against {dr} in {s:?}");
                }
            }
        }
        assert!(
            drawn > 100 && failed > 100,
            "drawn {drawn}, failed {failed}"
        );
    }

    /// Where both views know up, a sample is two pairs whose level edge is
    /// longer than the shortest allowed (an edge along up fixes no turn)
    /// and whose rise agrees within the tolerance.
    #[test]
    fn an_upright_sample_is_two_pairs_that_rise_alike() {
        let mut rng = SplitMix(9);
        let (n, m) = (12, 14);
        let (human, robot) = (cloud(&mut rng, n), cloud(&mut rng, m));
        let (human_d, robot_d) = (distances(&human), distances(&robot));
        let (h, r): (Vec<f64>, Vec<f64>) = (
            human.iter().map(|p| p.z).collect(),
            robot.iter().map(|p| p.z).collect(),
        );
        let order: Vec<usize> = (0..n).collect();
        let candidates: Vec<Vec<usize>> = (0..n).map(|_| (0..m).collect()).collect();
        let (tolerance, min_edge) = (0.05, 0.2);
        let edges = Edges {
            human: &human_d,
            robot: &robot_d,
            n,
            m,
            tolerance,
            min_edge,
            heights: Some((&h, &r)),
        };
        let mut consistent = Vec::new();
        let mut drawn = 0;
        for _ in 0..2000 {
            let Some(s) = draw_sample(&mut rng, &order, &candidates, &edges, 2, &mut consistent)
            else {
                continue;
            };
            drawn += 1;
            let ((i, a), (j, b)) = (s[0], s[1]);
            let rise = h[j] - h[i];
            let level = (human_d[i * n + j].powi(2) - rise * rise).sqrt();
            assert!(i != j && a != b, "{s:?}");
            assert!(level > min_edge, "level edge {level} in {s:?}");
            assert!((rise - (r[b] - r[a])).abs() <= tolerance, "rise in {s:?}");
            assert!((human_d[i * n + j] - robot_d[a * m + b]).abs() <= tolerance);
            // The third entry is not part of a two-pair sample.
            assert_eq!(s[2], s[0]);
        }
        assert!(drawn > 100, "drawn {drawn}");
    }

    /// Cutting a near-copy of a kept motion short once it cannot take that
    /// motion's place (or settle the search) changes no answer: every
    /// solution is the same to the bit with the cut and without it, with
    /// and without up vectors.
    #[test]
    fn cutting_near_copies_short_changes_no_answer() {
        let params = crate::Params::default();
        let cut_short = || CUT_SHORT.with(std::cell::Cell::get);
        let mut more = 0;
        // `vref bench solver`'s scenes with its noise near the spacing,
        // where no motion settles the search.
        for case in 0..4u64 {
            let scene = vref_sim::RigidScene::with_noise(48, 7 + case, 0.02).unwrap();
            let scene = if case % 2 == 0 {
                scene.upright().unwrap()
            } else {
                scene
            };
            let problem = crate::Problem::new(&scene.human, &scene.robot, params.beta).unwrap();
            let before = cut_short();
            let with_cut = super::super::solve(&problem, &params);
            let between = cut_short();
            COPIES_CUT.with(|c| c.set(false));
            let without = super::super::solve(&problem, &params);
            COPIES_CUT.with(|c| c.set(true));
            // Passes cut short with the cut, beyond those without it.
            more += (between - before).saturating_sub(cut_short() - between);
            // Compared whole, reported briefly (a solution prints long).
            assert!(with_cut == without, "case {case}: the solutions differ");
        }
        // The cut must have acted, or the comparison shows nothing.
        assert!(more > 20, "near-copies cut short: {more}");
    }
}
