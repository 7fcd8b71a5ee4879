use super::stability::{Stability, start};
use super::{Soft, SolveOptions};
use crate::{Problem, SmParams};

/// Leading eigenvector of S by power iteration from the uniform vector:
/// `v <- S v / ||S v||_2` until `||v_new - v||_2 < tol`.
pub(super) fn solve(problem: &Problem, params: &SmParams, options: SolveOptions<'_>) -> Soft {
    let len = problem.len();
    let mut v = match options.warm_start {
        Some(_) => {
            let mut v = start(options.warm_start, len);
            let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            v.iter_mut().for_each(|x| *x /= norm);
            v
        }
        None => vec![1.0 / (len as f64).sqrt(); len],
    };
    let mut stability = Stability::new(
        problem.n,
        problem.m,
        options.stop_when_stable,
        options.warm_start,
    );
    let mut next = vec![0.0; len];
    let mut soft = Soft {
        x: Vec::new(),
        iterations: 0,
        converged: false,
    };
    while soft.iterations < params.max_iter {
        soft.iterations += 1;
        problem.spatial.mul(&v, &mut next);
        let norm = next.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 {
            // S is zero: no spatial information, keep the uniform vector.
            soft.converged = true;
            break;
        }
        next.iter_mut().for_each(|x| *x /= norm);
        let change = super::vector::squared_distance(&next, &v).sqrt();
        std::mem::swap(&mut v, &mut next);
        if change < params.tol || stability.settled(&v) {
            soft.converged = true;
            break;
        }
    }
    soft.x = v;
    soft
}
