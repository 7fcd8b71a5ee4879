//! `clipper`: the consistency-graph method of robust data association
//! (Lusk, Fathian, How, "CLIPPER: A Graph-Theoretic Framework for Robust
//! Data Association", ICRA 2021), as an anchor of `rigid`'s own kind.
//!
//! The candidate pairs are those appearance keeps (the live tier's
//! candidates). Two pairs are consistent when they keep the distance
//! between their objects: weight `exp(-(d - d')^2 / beta)` (Eq. 3's kernel,
//! CLIPPER's `exp(-c^2 / 2 sigma^2)` with `2 sigma^2 = beta`), and 0 beyond
//! `epsilon` or when they share an object. The densest subgraph of that
//! weighted graph, `max u^T M u` over unit `u >= 0` with the inconsistent
//! pairs held apart, is found by CLIPPER's projected gradient ascent with a
//! growing penalty `d` on inconsistent pairs; its size estimate
//! `round(u^T M_d u)` picks the pairs kept, and a Hungarian assignment over
//! them makes the answer one-to-one. Objects outside the kept pairs get no
//! partner.
//!
//! Where both views know their up vector, a turn about up is the only
//! rotation left, so an edge's rise along up is kept as well as its length:
//! two pairs whose rises disagree by more than `epsilon` are inconsistent.
//! The rise gates and does not weigh: in the kernel too it took accuracy
//! down (sim mrc training seeds 0.370 to 0.329, against 0.385 as a gate),
//! every true edge's weight shrinking by its rise's noise.

use serde::{Deserialize, Serialize};

use crate::{LiveParams, MatchError, Params, Problem, Solution, candidate_pairs, hungarian_max};

/// Constants of `clipper`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ClipperParams {
    /// Largest distance disagreement of two consistent pairs, in units of
    /// the kernel's `sigma = sqrt(beta / 2)` (CLIPPER's `epsilon`).
    pub epsilon: f64,
    /// Gradient steps per value of the penalty `d` (CLIPPER's
    /// `maxiniters`).
    pub inner_iterations: usize,
    /// Values of the penalty `d` (CLIPPER's `maxoliters`).
    pub outer_iterations: usize,
    /// Keep CLIPPER's size estimate's largest entries of u, not the whole
    /// support of a converged u.
    pub size_estimate: bool,
}

impl Default for ClipperParams {
    fn default() -> Self {
        Self {
            epsilon: 3.0,
            inner_iterations: 200,
            outer_iterations: 1000,
            size_estimate: false,
        }
    }
}

impl ClipperParams {
    pub(crate) fn validate(&self) -> Result<(), MatchError> {
        if !(self.epsilon.is_finite() && self.epsilon > 0.0) {
            return Err(MatchError::BadParameter {
                name: "clipper.epsilon",
                value: self.epsilon,
                expected: "positive and finite",
            });
        }
        for (name, count) in [
            ("clipper.inner_iterations", self.inner_iterations),
            ("clipper.outer_iterations", self.outer_iterations),
        ] {
            if count == 0 {
                return Err(MatchError::BadParameter {
                    name,
                    value: 0.0,
                    expected: "at least 1",
                });
            }
        }
        Ok(())
    }
}

/// CLIPPER's stopping tolerances and line search, as in its reference code.
const TOL_U: f64 = 1e-8;
const TOL_F: f64 = 1e-9;
const TOL_FOP: f64 = 1e-10;
const BACKTRACK: f64 = 0.25;
const LINE_SEARCH: usize = 20;
const EPS: f64 = 1e-9;
/// Entries of u above this are in its support.
const SUPPORT: f64 = 1e-6;

pub(super) fn solve(problem: &Problem, params: &Params) -> Solution {
    let (n, m) = (problem.n, problem.m);
    let cp = &params.clipper;
    let pairs = gated_pairs(problem, &params.live);
    let graph = Consistency::new(problem, &pairs, params.beta, cp.epsilon);
    let (u, objective, iterations, converged) = densest(&graph, cp);
    let mut soft = vec![0.0; n * m];
    for (k, &(i, j)) in pairs.iter().enumerate() {
        soft[i * m + j] = u[k];
    }
    // The pairs kept: once the penalty has separated every inconsistent
    // pair, the support of u is a consistent cluster, and all of it is
    // kept. CLIPPER's size estimate round(u^T M_d u) counts a cluster of
    // weights below 1 short (a fifth to a third of the true pairs on the
    // training sets) and serves only when the penalty did not converge.
    let keep = if cp.size_estimate || !converged {
        let mut order: Vec<usize> = (0..pairs.len()).collect();
        order.sort_by(|&a, &b| u[b].total_cmp(&u[a]).then(pairs[a].cmp(&pairs[b])));
        let size = objective.round().max(0.0) as usize;
        order.truncate(size);
        order
    } else {
        (0..pairs.len()).filter(|&k| u[k] > SUPPORT).collect()
    };
    let mut scores = vec![0.0; n * m];
    for k in keep {
        let (i, j) = pairs[k];
        scores[i * m + j] = u[k];
    }
    let assignment: Vec<Option<usize>> = match hungarian_max(&scores, n, m) {
        Ok(h) => h
            .row_to_col
            .iter()
            .enumerate()
            .map(|(i, a)| a.filter(|&j| scores[i * m + j] > 0.0))
            .collect(),
        Err(_) => vec![None; n],
    };
    let confidence = assignment
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let row = &soft[i * m..(i + 1) * m];
            let total: f64 = row.iter().sum();
            let share = |v: f64| if total > 0.0 { v / total } else { 0.0 };
            match a {
                Some(j) => share(row[*j]),
                None => 1.0 - row.iter().map(|&v| share(v)).fold(0.0, f64::max),
            }
        })
        .collect();
    Solution {
        soft,
        assignment,
        confidence,
        iterations,
        converged,
        motion: None,
        margin: None,
        significance: None,
        fit: None,
        residuals: Vec::new(),
    }
}

/// The appearance-gated candidate pairs (human, robot), in row order.
fn gated_pairs(problem: &Problem, live: &LiveParams) -> Vec<(usize, usize)> {
    let m = problem.m;
    candidate_pairs(&problem.appearance, problem.n, m, live)
        .into_iter()
        .map(|f| (f / m, f % m))
        .collect()
}

/// The weighted consistency graph over candidate pairs: `weights` dense
/// row-major (1 on the diagonal).
struct Consistency {
    size: usize,
    weights: Vec<f64>,
}

impl Consistency {
    fn new(problem: &Problem, pairs: &[(usize, usize)], beta: f64, epsilon: f64) -> Self {
        let size = pairs.len();
        let hp = &problem.human_positions;
        let rp = &problem.robot_positions;
        let ups = problem.human_up.zip(problem.robot_up);
        let bound = epsilon * (beta / 2.0).sqrt();
        let mut weights = vec![0.0; size * size];
        for a in 0..size {
            weights[a * size + a] = 1.0;
            let (i, j) = pairs[a];
            for b in a + 1..size {
                let (k, l) = pairs[b];
                if i == k || j == l {
                    continue;
                }
                let (h, r) = (hp[i] - hp[k], rp[j] - rp[l]);
                let c = (h.norm() - r.norm()).abs();
                let rise = ups.map_or(0.0, |(hu, ru)| (hu.dot(&h) - ru.dot(&r)).abs());
                if c <= bound && rise <= bound {
                    let w = (-c * c / beta).exp();
                    weights[a * size + b] = w;
                    weights[b * size + a] = w;
                }
            }
        }
        Self { size, weights }
    }

    /// `M u` and `C̄ u` (C̄: 1 where two pairs are inconsistent).
    fn products(&self, u: &[f64], mu: &mut [f64], cbu: &mut [f64]) {
        let total: f64 = u.iter().sum();
        for a in 0..self.size {
            let row = &self.weights[a * self.size..(a + 1) * self.size];
            let (mut w, mut consistent) = (0.0, 0.0);
            for (&x, &v) in row.iter().zip(u) {
                w += x * v;
                if x > 0.0 {
                    consistent += v;
                }
            }
            mu[a] = w;
            cbu[a] = total - consistent;
        }
    }

    /// `u^T (M - d C̄) u`.
    fn quadratic(&self, u: &[f64], d: f64) -> f64 {
        let mut mu = vec![0.0; self.size];
        let mut cbu = vec![0.0; self.size];
        self.products(u, &mut mu, &mut cbu);
        u.iter()
            .zip(mu.iter().zip(&cbu))
            .map(|(x, (a, b))| x * (a - d * b))
            .sum()
    }
}

/// CLIPPER's projected gradient ascent: for each penalty `d`, ascend
/// `u^T M_d u` on the non-negative unit sphere; then raise `d` by the
/// least amount that makes an inconsistent pair's gradient negative.
/// Returns `u`, the objective of the last ascent, the gradient steps
/// taken, and whether the penalty stopped growing before the outer limit.
fn densest(graph: &Consistency, cp: &ClipperParams) -> (Vec<f64>, f64, usize, bool) {
    let size = graph.size;
    if size == 0 {
        return (Vec::new(), 0.0, 0, true);
    }
    let mut mu = vec![0.0; size];
    let mut cbu = vec![0.0; size];
    // One power step from the uniform vector (CLIPPER starts from a random
    // one; the uniform keeps the answer independent of the objects' order).
    let mut u = vec![1.0 / (size as f64).sqrt(); size];
    graph.products(&u, &mut mu, &mut cbu);
    u.copy_from_slice(&mu);
    normalise(&mut u);
    graph.products(&u, &mut mu, &mut cbu);
    let mut d = penalty_step(&u, &mu, &cbu).unwrap_or(0.0);
    let mut steps = 0;
    let mut converged = false;
    let mut next = vec![0.0; size];
    let mut gradient = vec![0.0; size];
    let mut f = 0.0;
    for _ in 0..cp.outer_iterations {
        f = graph.quadratic(&u, d);
        for _ in 0..cp.inner_iterations {
            steps += 1;
            graph.products(&u, &mut mu, &mut cbu);
            for k in 0..size {
                gradient[k] = mu[k] - d * cbu[k];
            }
            let along: f64 = gradient.iter().zip(&u).map(|(g, x)| g * x).sum();
            for (g, x) in gradient.iter_mut().zip(&u) {
                *g -= along * x;
            }
            let norm = gradient.iter().map(|g| g * g).sum::<f64>().sqrt();
            if norm < TOL_FOP {
                break;
            }
            let mut alpha = gradient
                .iter()
                .zip(&u)
                .filter(|(g, x)| **g < -EPS && **x > EPS)
                .map(|(g, x)| (x / g).abs())
                .fold(f64::INFINITY, f64::min);
            if !alpha.is_finite() {
                alpha = (1.0 / BACKTRACK).powi(3) / norm;
            }
            let mut f_next = f;
            for _ in 0..LINE_SEARCH {
                for k in 0..size {
                    next[k] = (u[k] + alpha * gradient[k]).max(0.0);
                }
                normalise(&mut next);
                f_next = graph.quadratic(&next, d);
                if f_next - f >= -EPS {
                    break;
                }
                alpha *= BACKTRACK;
            }
            let moved = next
                .iter()
                .zip(&u)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt();
            let change = (f_next - f).abs();
            u.copy_from_slice(&next);
            f = f_next;
            if moved < TOL_U || change < TOL_F {
                break;
            }
        }
        graph.products(&u, &mut mu, &mut cbu);
        match penalty_step(&u, &mu, &cbu) {
            Some(delta) => d += delta,
            None => {
                converged = true;
                break;
            }
        }
    }
    (u, f, steps, converged)
}

/// The least rise of `d` that makes some selected pair's gradient
/// `M u - d C̄ u` reach zero where it is inconsistent with the selection;
/// `None` when no selected pair is (the selection is consistent).
fn penalty_step(u: &[f64], mu: &[f64], cbu: &[f64]) -> Option<f64> {
    let step = u
        .iter()
        .zip(mu.iter().zip(cbu))
        .filter(|(x, (_, c))| **c > EPS && **x > EPS)
        .map(|(_, (a, c))| (a / c).abs())
        .fold(f64::INFINITY, f64::min);
    step.is_finite().then_some(step)
}

fn normalise(u: &mut [f64]) {
    let norm = u.iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm > 0.0 {
        u.iter_mut().for_each(|x| *x /= norm);
    }
}
