#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use proptest::prelude::*;
use vref_match::{MatchError, hungarian_max};

/// Best total over every injective map of the smaller side into the larger.
fn brute_force(scores: &[f64], rows: usize, cols: usize) -> f64 {
    fn go(
        scores: &[f64],
        rows: usize,
        cols: usize,
        r: usize,
        used: &mut Vec<bool>,
        transposed: bool,
    ) -> f64 {
        let (small, large) = if transposed {
            (cols, rows)
        } else {
            (rows, cols)
        };
        if r == small {
            return 0.0;
        }
        let mut best = f64::NEG_INFINITY;
        for c in 0..large {
            if !used[c] {
                used[c] = true;
                let s = if transposed {
                    scores[c * cols + r]
                } else {
                    scores[r * cols + c]
                };
                best = best.max(s + go(scores, rows, cols, r + 1, used, transposed));
                used[c] = false;
            }
        }
        best
    }
    let transposed = rows > cols;
    let mut used = vec![false; rows.max(cols)];
    go(scores, rows, cols, 0, &mut used, transposed)
}

fn matrix() -> impl Strategy<Value = (usize, usize, Vec<f64>)> {
    (1usize..=6, 1usize..=6).prop_flat_map(|(r, c)| {
        (
            Just(r),
            Just(c),
            prop::collection::vec(-10.0f64..10.0, r * c),
        )
    })
}

proptest! {
    #[test]
    fn total_equals_brute_force_optimum((rows, cols, scores) in matrix()) {
        let h = hungarian_max(&scores, rows, cols).unwrap();
        let best = brute_force(&scores, rows, cols);
        prop_assert!((h.total - best).abs() < 1e-9, "hungarian {} vs brute force {}", h.total, best);
    }

    #[test]
    fn assignment_is_one_to_one_and_complete((rows, cols, scores) in matrix()) {
        let h = hungarian_max(&scores, rows, cols).unwrap();
        let assigned: Vec<usize> = h.row_to_col.iter().flatten().copied().collect();
        prop_assert_eq!(assigned.len(), rows.min(cols));
        let mut unique = assigned.clone();
        unique.sort_unstable();
        unique.dedup();
        prop_assert_eq!(unique.len(), assigned.len());
        prop_assert!(assigned.iter().all(|&c| c < cols));
    }

    #[test]
    fn integer_scores_with_ties_still_optimal((rows, cols, scores) in matrix()) {
        let rounded: Vec<f64> = scores.iter().map(|s| (s / 5.0).round()).collect();
        let h = hungarian_max(&rounded, rows, cols).unwrap();
        prop_assert!((h.total - brute_force(&rounded, rows, cols)).abs() < 1e-9);
    }
}

#[test]
fn picks_the_anti_diagonal_when_it_is_best() {
    let scores = [1.0, 5.0, 4.0, 1.0];
    let h = hungarian_max(&scores, 2, 2).unwrap();
    assert_eq!(h.row_to_col, vec![Some(1), Some(0)]);
    assert_eq!(h.total, 9.0);
}

#[test]
fn more_rows_than_columns_leaves_the_worst_rows_unassigned() {
    // 3 rows, 1 column: only the best row gets it.
    let h = hungarian_max(&[0.1, 0.9, 0.5], 3, 1).unwrap();
    assert_eq!(h.row_to_col, vec![None, Some(0), None]);
}

#[test]
fn refuses_non_finite_scores_and_wrong_shapes() {
    assert!(matches!(
        hungarian_max(&[0.0, f64::NAN], 1, 2),
        Err(MatchError::NonFiniteScore { row: 0, col: 1, .. })
    ));
    assert!(matches!(
        hungarian_max(&[1.0, 2.0, 3.0], 2, 2),
        Err(MatchError::ShapeMismatch {
            len: 3,
            rows: 2,
            cols: 2
        })
    ));
}

#[test]
fn empty_matrix_assigns_nothing() {
    let h = hungarian_max(&[], 0, 3).unwrap();
    assert!(h.row_to_col.is_empty());
    assert_eq!(h.total, 0.0);
}
