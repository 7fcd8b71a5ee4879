//! `rigid`: vref's own method. Both views are rigid snapshots of one 3D
//! scene, so a single proper rotation and translation maps the human
//! view onto the robot's. The method finds it by RANSAC over candidate
//! pairs seeded by appearance, verifies every pair against it, and assigns
//! with a cost for leaving an object without a partner, so that objects
//! one camera alone sees stay unmatched. Its confidence is a calibrated
//! probability that the row's answer (a partner, or none) is right.

mod coincidence;
mod costs;
mod log1p;
mod motion;
mod moved;
mod noise;
mod params;
mod search;
mod side;
mod significance;
mod track;

use crate::{Params, Problem, Solution, hungarian_max};

use costs::Costs;
pub use motion::{RigidMotion, median_spacing};
pub use params::RigidParams;
use search::{chance_inliers, explained, largest_score, rescore, score_of, search};
pub(crate) use track::Track;

/// Score of a column a row must never take in the padded assignment.
const FORBIDDEN: f64 = -1e12;

pub(super) fn solve(problem: &Problem, params: &Params) -> Solution {
    solve_from(problem, params, None).0
}

/// Hypotheses the margin's null is sampled from: fewer where both views
/// know up, as the search itself draws fewer.
fn chance_samples(problem: &Problem, rp: &RigidParams) -> usize {
    if problem.gravity().is_some() {
        rp.chance_samples_upright
    } else {
        rp.chance_samples
    }
}

/// [`solve`], starting from what the last solve of the same (changing)
/// scene left (`last`) where its motions still explain the scene, instead
/// of searching; returns what this solve leaves for the next, and whether
/// it started from `last`.
pub(crate) fn solve_from(
    problem: &Problem,
    params: &Params,
    last: Option<&Track>,
) -> (Solution, Option<Track>, bool) {
    let rp = &params.rigid;
    let (n, m) = (problem.n, problem.m);
    let spacing = median_spacing(&problem.robot_positions).unwrap_or(params.beta.sqrt());
    let log_g = appearance_log_likelihood(problem, rp.appearance_temperature, rp.appearance_floor);
    let mut costs = Costs::new(problem, &log_g, spacing, rp);
    // The scales assumed (or stated) before the scene's own noise replaces
    // them: the prior of its estimate, and what the coincidence rule's fit
    // is measured under.
    let assumed = costs.rays.as_ref().map(|r| r.noise);
    let resumed = last.and_then(|t| track::resume(&costs, rp, t));
    let from = last.filter(|_| resumed.is_some());
    let mut found = resumed.or_else(|| {
        let seeds = consistency_seed(problem, params, costs.typical);
        search(&costs, costs.typical, rp, &seeds)
    });
    let search_score = found.as_ref().map_or(0.0, |f| f.score);
    // The noise this scene shows under its best motion replaces the
    // assumed one, and the kept motions are judged again under it; again,
    // since pairs the assumed scales cut off count once the scales widen.
    if rp.noise_prior > 0.0
        && let Some(prior) = assumed
    {
        for _ in 0..rp.noise_rounds {
            let Some(f) = &found else { break };
            let Some(adapted) = with_noise_under(&costs, rp, prior, &f.motion) else {
                break;
            };
            let settled = f.settled;
            let Some(again) = rescore(&adapted, rp, &f.kept, f.tests) else {
                break;
            };
            costs = adapted;
            found = Some(search::Found { settled, ..again });
        }
    }
    let mut motion = found.as_ref().map(|f| f.motion);
    let mut cost = costs.matrix(motion.as_ref());
    let mut assignment = assign(&cost, n, m, rp.unmatched_cost);
    let mut iterations = 0;
    let mut converged = motion.is_none();
    if motion.is_some() {
        for _ in 0..rp.refinements {
            iterations += 1;
            let Some(refit) = fit_assigned(problem, &assignment) else {
                break;
            };
            motion = Some(refit);
            cost = costs.matrix(motion.as_ref());
            let next = assign(&cost, n, m, rp.unmatched_cost);
            let same = next == assignment;
            assignment = next;
            if same {
                converged = true;
                break;
            }
        }
    }
    // The motion the answer rests on was re-fitted to its pairs after the
    // noise was estimated under the search's motion: its residuals are
    // the ones the answer's costs should know, so the noise is estimated
    // again under it (training files: accuracy up on three families of
    // four, down on none, across sampler seeds; docs/method.md).
    if let (Some(prior), Some(t)) = (assumed.filter(|_| rp.noise_prior > 0.0), motion)
        && let Some(adapted) = with_noise_under(&costs, rp, prior, &t)
    {
        costs = adapted;
        cost = costs.matrix(motion.as_ref());
        assignment = assign(&cost, n, m, rp.unmatched_cost);
    }
    let (soft, unmatched) = row_shares(&cost, n, m, rp.unmatched_cost);
    // How many pairs the motion explains against chance (`significance`):
    // its pairs as assigned, before any is withheld.
    let significance = motion.as_ref().and_then(|t| {
        let inliers: Vec<f64> = assignment
            .iter()
            .enumerate()
            .filter_map(|(i, a)| a.map(|j| cost[i * m + j]))
            .collect();
        let chance = chance_costs(problem, &log_g, spacing, rp, &costs, t);
        significance::log10_nfa(&inliers, n, &chance).map(|l| -l)
    });
    // How far the motion stands above what chance explains in a view of
    // this scene that no motion explains: the calibration weighs it.
    let margin = match &found {
        _ if from.is_some() => from.map(|t| t.margin),
        Some(f) if chance_samples(problem, rp) > 0 && !f.settled => {
            let best = motion.as_ref().unwrap_or(&f.motion);
            let null = coincidence::null_view(problem, rp.seed);
            let mut null_costs = Costs::new(&null, &log_g, spacing, rp);
            if let Some(noise) = costs.rays.as_ref().map(|r| r.noise) {
                null_costs = null_costs.with_noise(noise);
            }
            let chance = chance_inliers(&null_costs, rp, chance_samples(problem, rp), None);
            coincidence::margin(&chance, score_of(&costs, rp, best), f.tests)
        }
        _ => None,
    }
    .unwrap_or(f64::INFINITY);
    let keep = rp.local_optimisations.max(1) + 1;
    let track = found
        .as_ref()
        .map(|f| Track::after(f, search_score, motion, margin, from, keep));

    // The rival motions: each is weighed against the best by its score,
    // and a row's answer is only as sure as the motions that give it.
    let mut weights = Vec::new();
    let mut rivals = Vec::new();
    if let Some(f) = &found {
        for &(score, alt) in &f.alternatives {
            let w = ((score - f.score) / rp.motion_temperature).exp();
            if w > 1e-9 {
                weights.push(w);
                rivals.push(assign(&costs.matrix(Some(&alt)), n, m, rp.unmatched_cost));
            }
        }
    }
    let total = 1.0 + weights.iter().sum::<f64>();
    let p_best = 1.0 / total;
    let mut confidence = Vec::with_capacity(n);
    // The best of the partners abstention takes back, in case it takes
    // them all: (raw share, row, partner).
    let mut withdrawn: Option<(f64, usize, usize)> = None;
    let disputed = p_best < rp.abstain_motion;
    let fit = motion
        .as_ref()
        .map_or(0.0, |t| assumed_fit(&costs, assumed, rp, t));
    let measures_of = |assignment: &[Option<usize>]| coincidence::Measures {
        significance,
        margin,
        share: assignment.iter().flatten().count() as f64 / n.min(m).max(1) as f64,
        fit,
    };
    // Withholding a disputed partner trades accuracy for precision. A
    // motion far above chance is disputed by rivals over a few rows of the
    // scene it explains, and those partners are mostly right: on the
    // training files a lower share there raised sim mrc's accuracy in
    // every sampler seed tried, and let about as many unrelated views
    // through (docs/method.md).
    let evident = rp.abstain_evidence < f64::INFINITY
        && coincidence::evidence(&measures_of(&assignment), rp) >= rp.abstain_evidence;
    let abstain_share = if evident {
        rp.abstain_share_evident
    } else {
        rp.abstain_share
    };
    for i in 0..n {
        let against: f64 = rivals
            .iter()
            .zip(&weights)
            .filter(|(alt, _)| alt[i] != assignment[i])
            .map(|(_, w)| w)
            .sum();
        let agrees = against == 0.0;
        let motion_share = 1.0 - against / total;
        let mut raw = motion_share
            * match assignment[i] {
                Some(j) => soft[i * m + j],
                None => unmatched[i],
            };
        // Abstaining: a partner the runner-up motion disputes and that is
        // this unsure is not given (precision); the object is answered "no
        // partner" with that answer's share. Decided on the raw share, so
        // that the calibration is fitted to the answers as finally given.
        if let Some(j) = assignment[i]
            && disputed
            && !agrees
            && raw < abstain_share
        {
            if withdrawn.is_none_or(|(best, _, _)| raw > best) {
                withdrawn = Some((raw, i, j));
            }
            assignment[i] = None;
            raw = unmatched[i];
        }
        confidence.push(raw);
    }
    if rp.never_empty
        && assignment.iter().all(Option::is_none)
        && let Some((raw, i, j)) = withdrawn
    {
        assignment[i] = Some(j);
        confidence[i] = raw;
    }
    // A motion is taken as chance when its evidence against chance (its
    // significance, its margin, how much of the scene it pairs and how
    // well, each of which alone lets through unrelated views that real
    // ones resemble) is low: docs/method.md, "Coincidence".
    let measures = measures_of(&assignment);
    // Without a motion (a view of under three objects fixes none, and a
    // search may find no sample that holds) the partners rest on
    // appearance alone: a lone pair has nothing to check it, and two pairs
    // fit their own swap as well as themselves.
    let significant = motion.is_some()
        && (!rp.chance_rule || coincidence::evidence(&measures, rp) >= rp.evidence_floor);
    for (c, a) in confidence.iter_mut().zip(&assignment) {
        *c = rp.calibration.probability(*c, a.is_none(), margin);
        // A partner resting on a motion that chance explains as well, or
        // on none, is not given as sure: at most `chance_cap`.
        if a.is_some() && !significant {
            *c = c.min(rp.chance_cap);
        }
    }
    // Objects both views leave unpaired whose looks single each other out:
    // an object moved between the views, which no motion explains, given
    // the partner its look names, never as sure (docs/method.md, "An
    // object that moved").
    if motion.is_some() {
        for (i, j) in
            moved::partners_by_look(&problem.appearance, n, m, &assignment, rp.moved_look_gap)
        {
            assignment[i] = Some(j);
            confidence[i] = rp.chance_cap;
        }
    }
    let residuals = crate::pair_residuals(problem, &assignment, motion.as_ref());
    let solution = Solution {
        residuals,
        soft,
        assignment,
        confidence,
        iterations,
        converged,
        motion,
        margin: margin.is_finite().then_some(margin),
        significance,
        fit: motion.as_ref().map(|_| measures.fit),
    };
    (solution, track, from.is_some())
}

/// The motion of the densest consistent cluster of candidate pairs
/// (`clipper`, with the distance tolerance of rigid's own typical pair
/// scale rather than the published methods' bandwidth), as one more
/// hypothesis; none above `clipper_seed_pairs` candidate pairs, where the
/// cluster search costs more than the live budget allows.
fn consistency_seed(problem: &Problem, params: &Params, typical: f64) -> Vec<RigidMotion> {
    let rp = &params.rigid;
    if problem.n * problem.m > rp.clipper_seed_pairs || problem.n < 3 || problem.m < 3 {
        return Vec::new();
    }
    let own = Params {
        beta: 2.0 * typical * typical,
        ..*params
    };
    let cluster = super::clipper::solve(problem, &own);
    fit_assigned(problem, &cluster.assignment)
        .into_iter()
        .collect()
}

/// `costs` with the noise scales that the residuals of the pairs `motion`
/// explains show, the `prior` counting as `rp.noise_prior` pairs; `None`
/// where they cannot be estimated (under three pairs, no rays).
fn with_noise_under<'a>(
    costs: &Costs<'a>,
    rp: &RigidParams,
    prior: costs::Noise,
    motion: &RigidMotion,
) -> Option<Costs<'a>> {
    let pairs = explained(costs, rp, motion);
    noise::estimate(costs, motion, &pairs, prior, rp.noise_prior)
        .map(|noise| costs.with_noise(noise))
}

/// The coincidence rule's fit: `motion`'s score under the `assumed` noise
/// scales (where the scene's own replaced them) over the largest possible.
/// Under the scene's own scales a motion that explains pairs by chance
/// widens the noise until its residuals look ordinary, and fits as well as
/// a real one; under the assumed scales it cannot buy its fit that way.
fn assumed_fit(
    costs: &Costs<'_>,
    assumed: Option<costs::Noise>,
    rp: &RigidParams,
    motion: &RigidMotion,
) -> f64 {
    let current = costs.rays.as_ref().map(|r| r.noise);
    let score = match assumed {
        // Cost tables are rebuilt only where the scene's noise replaced them.
        Some(noise) if current != Some(noise) => score_of(&costs.with_noise(noise), rp, motion),
        _ => score_of(costs, rp, motion),
    };
    score / largest_score(costs.problem.n, costs.problem.m, rp)
}

/// `(a - max of the row) / temperature`: the log of an appearance
/// likelihood relative to the row's best; all 0 without features.
fn appearance_log_likelihood(problem: &Problem, temperature: f64, floor: f64) -> Vec<f64> {
    let m = problem.m;
    let mut out = Vec::with_capacity(problem.len());
    for row in problem.appearance.chunks(m) {
        let best = row.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        out.extend(
            row.iter()
                .map(|&a| ((1.0 - floor) * ((a - best) / temperature).exp() + floor).ln()),
        );
    }
    out
}

/// Null views drawn at most per solve for the chance costs.
const MAX_NULL_VIEWS: usize = 64;

/// The chance costs of [`significance`]: every row's cheapest pair under
/// `motion` in views of this scene whose human places are shuffled in
/// their plane (about `rp.chance_rows` rows in all, at least one view),
/// with the scene's noise scales; sorted ascending. Empty when off.
fn chance_costs(
    problem: &Problem,
    log_g: &[f64],
    spacing: f64,
    rp: &RigidParams,
    costs: &Costs<'_>,
    motion: &RigidMotion,
) -> Vec<f64> {
    let n = problem.n;
    if n == 0 || problem.m == 0 || rp.chance_rows == 0 {
        return Vec::new();
    }
    let views = rp.chance_rows.div_ceil(n).clamp(1, MAX_NULL_VIEWS);
    let mut out = Vec::with_capacity(views * n);
    let mut buf = costs::RowScratch::default();
    for v in 0..views {
        let null = coincidence::null_view(problem, rp.seed.wrapping_add(v as u64));
        let mut null_costs = Costs::new(&null, log_g, spacing, rp);
        if let Some(noise) = costs.rays.as_ref().map(|r| r.noise) {
            null_costs = null_costs.with_noise(noise);
        }
        // The row's cheapest pair, to the bit what scanning the row finds,
        // with fewer logarithms.
        for i in 0..n {
            let [(cheapest, _), _] = null_costs.cheapest_two(i, motion, f64::INFINITY, &mut buf);
            out.push(cheapest);
        }
    }
    out.sort_by(f64::total_cmp);
    out
}

/// The motion re-fitted to the assigned pairs; `None` below three pairs.
fn fit_assigned(problem: &Problem, assignment: &[Option<usize>]) -> Option<RigidMotion> {
    let (from, to): (Vec<_>, Vec<_>) = assignment
        .iter()
        .enumerate()
        .filter_map(|(i, a)| a.map(|j| (problem.human_positions[i], problem.robot_positions[j])))
        .unzip();
    if from.len() < 3 {
        return None;
    }
    problem.fit_motion(&from, &to, &vec![1.0; from.len()])
}

/// Minimum-cost assignment in which every human object may instead stay
/// unmatched at cost `unmatched`: the robot side is padded with one
/// private "no partner" column per row.
fn assign(cost: &[f64], n: usize, m: usize, unmatched: f64) -> Vec<Option<usize>> {
    let width = m + n;
    let mut scores = vec![FORBIDDEN; n * width];
    for i in 0..n {
        for j in 0..m {
            scores[i * width + j] = -cost[i * m + j];
        }
        scores[i * width + m + i] = -unmatched;
    }
    match hungarian_max(&scores, n, width) {
        Ok(h) => h
            .row_to_col
            .into_iter()
            .map(|a| a.filter(|&j| j < m))
            .collect(),
        // Only non-finite costs fail, which the costs above never are
        // for finite inputs; no partner is the safe answer.
        Err(_) => vec![None; n],
    }
}

/// Each row's softmax over its robot objects and "no partner"
/// (`exp(-cost)`, normalised): the soft answer, and the share of "no
/// partner" per row.
fn row_shares(cost: &[f64], n: usize, m: usize, unmatched: f64) -> (Vec<f64>, Vec<f64>) {
    let mut soft = vec![0.0; n * m];
    let mut none = vec![0.0; n];
    for i in 0..n {
        let row = &cost[i * m..(i + 1) * m];
        let low = row.iter().copied().fold(unmatched, f64::min);
        let mut z = (low - unmatched).exp();
        for (s, &c) in soft[i * m..(i + 1) * m].iter_mut().zip(row) {
            *s = (low - c).exp();
            z += *s;
        }
        soft[i * m..(i + 1) * m].iter_mut().for_each(|s| *s /= z);
        none[i] = (low - unmatched).exp() / z;
    }
    (soft, none)
}

/// The partners `rigid` gives under `motion`, as if its search had found
/// it: the scene's own noise estimated from the pairs `motion` explains,
/// then the assignment with "no partner" (no re-fit, no abstention). Each
/// row `i` is costed under `rows[i]` where `rows` is not empty (a motion
/// per row, e.g. one fitted without that row's own pair). For diagnosis
/// (vref-research's `examples/rigid_ceiling.rs`): under the true motion it
/// is what rigid's costs would answer had the search not erred.
#[cfg(feature = "research")]
pub fn assignment_under(
    problem: &Problem,
    params: &Params,
    motion: &RigidMotion,
    rows: &[RigidMotion],
) -> Vec<Option<usize>> {
    let rp = &params.rigid;
    let (n, m) = (problem.n, problem.m);
    let spacing = median_spacing(&problem.robot_positions).unwrap_or(params.beta.sqrt());
    let log_g = appearance_log_likelihood(problem, rp.appearance_temperature, rp.appearance_floor);
    let mut costs = Costs::new(problem, &log_g, spacing, rp);
    if rp.noise_prior > 0.0
        && let Some(prior) = costs.rays.as_ref().map(|r| r.noise)
    {
        for _ in 0..rp.noise_rounds {
            let Some(adapted) = with_noise_under(&costs, rp, prior, motion) else {
                break;
            };
            costs = adapted;
        }
    }
    let mut cost = vec![0.0; n * m];
    for (i, out) in cost.chunks_mut(m.max(1)).enumerate().take(n) {
        costs.row(i, rows.get(i).unwrap_or(motion), out);
    }
    assign(&cost, n, m, rp.unmatched_cost)
}
