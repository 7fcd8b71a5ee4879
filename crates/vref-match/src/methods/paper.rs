use super::stability::{Stability, start};
use super::vector::{amplify, max, normalize_sum, squared_distance, sum};
use super::{Soft, SolveOptions};
use crate::{Params, Problem, sinkhorn_slack};

/// The paper's Algorithm 1, appearance-guided reweighted jumps, with the
/// choices of ALGORITHMS.md: both terms of w L1-normalised.
pub(super) fn solve(problem: &Problem, params: &Params, options: SolveOptions<'_>) -> Soft {
    let pp = &params.paper;
    let (n, m, len) = (problem.n, problem.m, problem.len());
    let max_row_sum = problem.spatial.max_row_sum();

    // a+ = max(a, 0); q = a+ / max(a+), used L1-normalised in w (Eq. 6).
    let a_plus: Vec<f64> = problem.appearance.iter().map(|&a| a.max(0.0)).collect();
    let mut q = if max(&a_plus) > 0.0 {
        a_plus.clone()
    } else {
        vec![1.0; len]
    };
    normalize_sum(&mut q);

    let mut x = start(options.warm_start, len);
    let mut x_prev = x.clone();
    let mut stability = Stability::new(n, m, options.stop_when_stable, options.warm_start);
    let mut z = vec![0.0; len];
    let mut walk = vec![0.0; len];
    let mut next = vec![0.0; len];
    let mut soft = Soft {
        x: Vec::new(),
        iterations: 0,
        converged: false,
    };
    while soft.iterations < pp.max_iter {
        soft.iterations += 1;
        // z: appearance-weighted current answer, amplified and made
        // bistochastic (Eq. 8).
        for ((zi, xi), ai) in z.iter_mut().zip(&x).zip(&a_plus) {
            *zi = xi * ai;
        }
        amplify(&mut z, 1.0);
        sinkhorn_slack(
            &mut z,
            n,
            m,
            params.sinkhorn_tol,
            params.sinkhorn_max_rounds,
        );
        normalize_sum(&mut z);

        // P^T x = P x (S is symmetric), L1-normalised; all zero when there
        // is no spatial structure.
        problem.spatial.mul(&x, &mut walk);
        if max_row_sum > 0.0 {
            walk.iter_mut().for_each(|v| *v /= max_row_sum);
        }
        let walk_sum = sum(&walk);
        for k in 0..len {
            let spatial = if walk_sum > 0.0 {
                walk[k] / walk_sum
            } else {
                0.0
            };
            let w = pp.lambda1 * q[k] + pp.lambda2 * spatial;
            next[k] = pp.alpha * w + (1.0 - pp.alpha) * z[k];
        }
        normalize_sum(&mut next);

        let change = squared_distance(&next, &x).min(squared_distance(&next, &x_prev));
        std::mem::swap(&mut x_prev, &mut x);
        x.copy_from_slice(&next);
        if change < pp.tol || stability.settled(&x) {
            soft.converged = true;
            break;
        }
    }
    soft.x = x;
    soft
}
