#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use proptest::prelude::*;
use vref_match::sinkhorn_slack;

const TOL: f64 = 1e-3;

fn positive_matrix() -> impl Strategy<Value = (usize, usize, Vec<f64>)> {
    (1usize..=9, 1usize..=9).prop_flat_map(|(n, m)| {
        (
            Just(n),
            Just(m),
            prop::collection::vec(0.01f64..100.0, n * m),
        )
    })
}

fn row_sums(x: &[f64], n: usize, m: usize) -> Vec<f64> {
    (0..n).map(|i| x[i * m..(i + 1) * m].iter().sum()).collect()
}

fn col_sums(x: &[f64], n: usize, m: usize) -> Vec<f64> {
    (0..m).map(|a| (0..n).map(|i| x[i * m + a]).sum()).collect()
}

proptest! {
    /// The larger side's lines sum to 1 within the tolerance; the smaller
    /// side's lines give up mass to the slack and never exceed 1.
    #[test]
    fn rows_and_columns_meet_the_tolerance((n, m, mut x) in positive_matrix()) {
        let out = sinkhorn_slack(&mut x, n, m, TOL, 1000);
        prop_assert!(out.converged, "did not converge in {} rounds", out.rounds);
        let (rows, cols) = (row_sums(&x, n, m), col_sums(&x, n, m));
        if n <= m {
            for r in &rows { prop_assert!((r - 1.0).abs() <= TOL, "row sum {}", r); }
            for c in &cols { prop_assert!(*c <= 1.0 + 1e-9, "column sum {}", c); }
        }
        if m <= n {
            for c in &cols { prop_assert!((c - 1.0).abs() <= TOL, "column sum {}", c); }
            for r in &rows { prop_assert!(*r <= 1.0 + TOL, "row sum {}", r); }
        }
        prop_assert!(x.iter().all(|v| v.is_finite() && *v >= 0.0));
    }

    /// With slack, the total real mass is the number of lines on the
    /// smaller side (within the tolerance per line).
    #[test]
    fn total_mass_is_the_smaller_side((n, m, mut x) in positive_matrix()) {
        sinkhorn_slack(&mut x, n, m, TOL, 1000);
        let total: f64 = x.iter().sum();
        prop_assert!((total - n.min(m) as f64).abs() <= TOL * n.max(m) as f64, "total {}", total);
    }
}

#[test]
fn square_matrix_becomes_doubly_stochastic() {
    let mut x = vec![1.0, 2.0, 3.0, 4.0];
    let out = sinkhorn_slack(&mut x, 2, 2, 1e-9, 1000);
    assert!(out.converged);
    for s in row_sums(&x, 2, 2).iter().chain(&col_sums(&x, 2, 2)) {
        assert!((s - 1.0).abs() < 1e-8);
    }
}

#[test]
fn slack_keeps_an_unpartnered_column_from_being_forced_to_one() {
    // One row, two columns: without slack the column pass would scale both
    // columns to 1 and the row to 2; with slack the row sums to 1 and the
    // columns keep the row's preference.
    let mut x = vec![3.0, 1.0];
    sinkhorn_slack(&mut x, 1, 2, 1e-9, 1000);
    assert!((x[0] + x[1] - 1.0).abs() < 1e-8);
    assert!(x[0] > x[1]);
}

#[test]
fn stops_at_the_round_limit() {
    // Entry (0,0) lies on no perfect matching of the support, so it only
    // decays like 1/k and the tolerance cannot be met in two rounds.
    let mut x = vec![1.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0];
    let out = sinkhorn_slack(&mut x, 3, 3, 1e-12, 2);
    assert_eq!(out.rounds, 2);
    assert!(!out.converged);
}
