/// How a Sinkhorn normalisation ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sinkhorn {
    /// Row-then-column rounds performed.
    pub rounds: usize,
    /// Whether every row and column sum came within the tolerance.
    pub converged: bool,
}

/// Bistochastic normalisation of the row-major `n x m` matrix `x` in place
/// (ALGORITHMS.md): rows and columns are scaled alternately until every sum
/// is within `tol` of its target, at most `max_rounds` rounds.
///
/// When `n != m` the smaller side is padded with slack of value 1, so that
/// real rows (or columns) with no partner are not forced to sum to 1. The
/// padding is held as one slack row (or column) whose target is the number
/// of missing rows (columns): `k` identical slack rows of target 1, as
/// RRWM.m pads, scale identically and so give the same real entries.
///
/// Entries must be non-negative; a row or column summing to 0 is left as
/// it is.
pub fn sinkhorn_slack(x: &mut [f64], n: usize, m: usize, tol: f64, max_rounds: usize) -> Sinkhorn {
    let rows = n + usize::from(n < m);
    let cols = m + usize::from(m < n);
    let mut padded = vec![1.0; rows * cols];
    for i in 0..n {
        padded[i * cols..i * cols + m].copy_from_slice(&x[i * m..(i + 1) * m]);
    }
    let row_target = |i: usize| if i < n { 1.0 } else { (m - n) as f64 };
    let col_target = |a: usize| if a < m { 1.0 } else { (n - m) as f64 };

    let mut col_factor = vec![0.0; cols];
    // Row sums of the current matrix: the convergence check of one round
    // computes them, and the next round's row pass needs exactly them (the
    // same sums over the same values in the same order), so they are kept.
    let mut row_sums: Vec<f64> = padded
        .chunks_exact(cols)
        .map(|row| row.iter().sum())
        .collect();
    let mut outcome = Sinkhorn {
        rounds: 0,
        converged: false,
    };
    while outcome.rounds < max_rounds {
        outcome.rounds += 1;
        for (i, &sum) in row_sums.iter().enumerate() {
            let row = &mut padded[i * cols..(i + 1) * cols];
            if sum > 0.0 {
                let factor = row_target(i) / sum;
                row.iter_mut().for_each(|v| *v *= factor);
            }
        }
        // Column sums accumulated row by row (contiguous, vectorised) add
        // the same terms in the same order as a walk down each column.
        col_factor.fill(0.0);
        for row in padded.chunks_exact(cols) {
            col_factor.iter_mut().zip(row).for_each(|(c, v)| *c += v);
        }
        for (a, c) in col_factor.iter_mut().enumerate() {
            *c = if *c > 0.0 { col_target(a) / *c } else { 1.0 };
        }
        for row in padded.chunks_exact_mut(cols) {
            row.iter_mut().zip(&col_factor).for_each(|(v, f)| *v *= f);
        }
        // Columns are exact after their pass; only rows can be off.
        for (sum, row) in row_sums.iter_mut().zip(padded.chunks_exact(cols)) {
            *sum = row.iter().sum();
        }
        let worst = row_sums
            .iter()
            .enumerate()
            .map(|(i, sum)| (sum - row_target(i)).abs())
            .fold(0.0, f64::max);
        if worst <= tol {
            outcome.converged = true;
            break;
        }
    }
    for i in 0..n {
        x[i * m..(i + 1) * m].copy_from_slice(&padded[i * cols..i * cols + m]);
    }
    outcome
}
