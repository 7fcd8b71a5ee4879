use crate::MatchError;

/// An optimal assignment.
#[derive(Debug, Clone, PartialEq)]
pub struct Hungarian {
    /// For each row, the column it is assigned to; `None` only for rows
    /// beyond the number of columns.
    pub row_to_col: Vec<Option<usize>>,
    /// Sum of the scores of the assigned pairs.
    pub total: f64,
}

/// Exact rectangular linear assignment maximising the total score of the
/// row-major `rows x cols` matrix: every row (if rows <= cols) or every
/// column (otherwise) gets exactly one partner.
///
/// Shortest augmenting paths with potentials (Kuhn-Munkres in the
/// Jonker-Volgenant form), O(k^2 K) for k = min and K = max side.
pub fn hungarian_max(scores: &[f64], rows: usize, cols: usize) -> Result<Hungarian, MatchError> {
    if scores.len() != rows * cols {
        return Err(MatchError::ShapeMismatch {
            len: scores.len(),
            rows,
            cols,
        });
    }
    if let Some((k, &value)) = scores.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(MatchError::NonFiniteScore {
            row: k / cols.max(1),
            col: k % cols.max(1),
            value,
        });
    }
    let row_to_col = if rows <= cols {
        assign(rows, cols, |i, j| -scores[i * cols + j])
    } else {
        let col_to_row = assign(cols, rows, |j, i| -scores[i * cols + j]);
        let mut row_to_col = vec![None; rows];
        for (j, i) in col_to_row.into_iter().enumerate() {
            if let Some(i) = i {
                row_to_col[i] = Some(j);
            }
        }
        row_to_col
    };
    let total = row_to_col
        .iter()
        .enumerate()
        .filter_map(|(i, j)| j.map(|j| scores[i * cols + j]))
        .sum();
    Ok(Hungarian { row_to_col, total })
}

/// Minimum-cost assignment of every one of `n` rows to distinct columns
/// among `m >= n`; `cost` must be finite.
fn assign(n: usize, m: usize, cost: impl Fn(usize, usize) -> f64) -> Vec<Option<usize>> {
    // 1-based with index 0 as the virtual start column, as in the classic
    // formulation; `owner[j]` is the row holding column j (0: free).
    let mut u = vec![0.0; n + 1];
    let mut v = vec![0.0; m + 1];
    let mut owner = vec![0usize; m + 1];
    let mut way = vec![0usize; m + 1];
    let mut min_reduced = vec![f64::INFINITY; m + 1];
    let mut used = vec![false; m + 1];
    for row in 1..=n {
        owner[0] = row;
        let mut j0 = 0;
        min_reduced.fill(f64::INFINITY);
        used.fill(false);
        loop {
            used[j0] = true;
            let i0 = owner[j0];
            let mut delta = f64::INFINITY;
            let mut j1 = 0;
            for j in 1..=m {
                if used[j] {
                    continue;
                }
                let reduced = cost(i0 - 1, j - 1) - u[i0] - v[j];
                if reduced < min_reduced[j] {
                    min_reduced[j] = reduced;
                    way[j] = j0;
                }
                if min_reduced[j] < delta {
                    delta = min_reduced[j];
                    j1 = j;
                }
            }
            for j in 0..=m {
                if used[j] {
                    u[owner[j]] += delta;
                    v[j] -= delta;
                } else {
                    min_reduced[j] -= delta;
                }
            }
            j0 = j1;
            if owner[j0] == 0 {
                break;
            }
        }
        while j0 != 0 {
            let j1 = way[j0];
            owner[j0] = owner[j1];
            j0 = j1;
        }
    }
    let mut row_to_col = vec![None; n];
    for j in 1..=m {
        if owner[j] != 0 {
            row_to_col[owner[j] - 1] = Some(j - 1);
        }
    }
    row_to_col
}
