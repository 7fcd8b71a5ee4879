use super::stability::{Stability, start};
use super::vector::{amplify, normalize_sum, squared_distance};
use super::{Soft, SolveOptions};
use crate::{Params, Problem, sinkhorn_slack};

/// Reweighted random walks with the semantics of the authors' RRWM.m:
/// walk on `P = S / max column sum`, jump to the Sinkhorn-normalised
/// amplification of the current walk distribution.
pub(super) fn solve(problem: &Problem, params: &Params, options: SolveOptions<'_>) -> Soft {
    let rp = &params.rrwm;
    let (n, m, len) = (problem.n, problem.m, problem.len());
    let max_degree = problem.spatial.max_row_sum();
    let mut x = start(options.warm_start, len);
    let mut x_prev = x.clone();
    let mut jump = x.clone();
    let mut stability = Stability::new(n, m, options.stop_when_stable, options.warm_start);
    let mut mix = vec![0.0; len];
    let mut y = vec![0.0; len];
    let mut soft = Soft {
        x: Vec::new(),
        iterations: 0,
        converged: false,
    };
    while soft.iterations < rp.max_iter {
        soft.iterations += 1;
        for ((t, xi), pi) in mix.iter_mut().zip(&x).zip(&jump) {
            *t = rp.c * xi + (1.0 - rp.c) * pi;
        }
        problem.spatial.mul(&mix, &mut y);
        if max_degree > 0.0 {
            y.iter_mut().for_each(|v| *v /= max_degree);
        }
        normalize_sum(&mut y);

        jump.copy_from_slice(&y);
        amplify(&mut jump, rp.amplification);
        sinkhorn_slack(
            &mut jump,
            n,
            m,
            params.sinkhorn_tol,
            params.sinkhorn_max_rounds,
        );
        normalize_sum(&mut jump);

        let change = squared_distance(&y, &x).min(squared_distance(&y, &x_prev));
        std::mem::swap(&mut x_prev, &mut x);
        x.copy_from_slice(&y);
        if change < rp.tol || stability.settled(&x) {
            soft.converged = true;
            break;
        }
    }
    soft.x = x;
    soft
}
