//! The live tier's candidate pairs: which robot objects a human object may
//! be matched to, chosen by appearance before any spatial work.

use crate::LiveParams;

/// Spread below which a row has no appearance information (no features,
/// or all partners look the same): pruning it would be a guess.
const NO_SPREAD: f64 = 1e-12;

/// Flat indices `i * m + a` of the candidate pairs of the row-major `n x m`
/// appearance affinity, ascending.
///
/// A human object keeps its `candidates_min` most similar robot objects and
/// every one within `appearance_margin` of its best, at most
/// `candidates_max` (identical-looking objects therefore all stay, up to the
/// cap); a row with no spread keeps every pair. Each robot object also
/// keeps its `candidates_min` most similar human objects, so that no robot
/// object loses every partner.
pub fn candidate_pairs(appearance: &[f64], n: usize, m: usize, live: &LiveParams) -> Vec<usize> {
    let mut keep = vec![false; n * m];
    let mut order: Vec<usize> = Vec::with_capacity(n.max(m));
    for i in 0..n {
        let row = &appearance[i * m..(i + 1) * m];
        mark_best(row, live, true, &mut order, |a| keep[i * m + a] = true);
    }
    let mut column = vec![0.0; n];
    for a in 0..m {
        for (i, c) in column.iter_mut().enumerate() {
            *c = appearance[i * m + a];
        }
        mark_best(&column, live, false, &mut order, |i| keep[i * m + a] = true);
    }
    keep.iter()
        .enumerate()
        .filter_map(|(k, &kept)| kept.then_some(k))
        .collect()
}

/// Calls `mark` with the indices of `values` to keep: the best
/// `candidates_min`, and with `within_margin` those near the best up to
/// `candidates_max`; all of them when `values` has no spread.
fn mark_best(
    values: &[f64],
    live: &LiveParams,
    within_margin: bool,
    order: &mut Vec<usize>,
    mut mark: impl FnMut(usize),
) {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let spread = hi - lo;
    if spread.is_nan() || spread <= NO_SPREAD {
        (0..values.len()).for_each(&mut mark);
        return;
    }
    order.clear();
    order.extend(0..values.len());
    // Descending by value; ties by index so the choice is deterministic.
    order.sort_by(|&p, &q| values[q].total_cmp(&values[p]).then(p.cmp(&q)));
    let cap = if within_margin {
        live.candidates_max
    } else {
        live.candidates_min
    };
    for (rank, &k) in order.iter().enumerate().take(cap) {
        let near = within_margin && values[k] >= hi - live.appearance_margin;
        if rank < live.candidates_min || near {
            mark(k);
        } else {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    fn live(min: usize, max: usize, margin: f64) -> LiveParams {
        LiveParams {
            candidates_min: min,
            candidates_max: max,
            appearance_margin: margin,
            ..LiveParams::default()
        }
    }

    #[test]
    fn keeps_the_best_and_every_look_alike_up_to_the_cap() {
        // Row 0: three identical apples at 0.95, a pear at 0.9, two others
        // far below. Row 1 is every column's best, so the column rule adds
        // nothing to row 0.
        let mut a = vec![0.2, 0.95, 0.9, 0.95, 0.1, 0.95];
        a.extend([0.99, 0.99, 0.99, 0.99, 0.99, 1.0]);
        let row0 = |pairs: Vec<usize>| pairs.into_iter().filter(|&k| k < 6).collect::<Vec<_>>();
        assert_eq!(
            row0(candidate_pairs(&a, 2, 6, &live(1, 10, 0.1))),
            vec![1, 2, 3, 5]
        );
        assert_eq!(
            row0(candidate_pairs(&a, 2, 6, &live(1, 2, 0.1))),
            vec![1, 3]
        );
        assert_eq!(
            row0(candidate_pairs(&a, 2, 6, &live(1, 10, 0.0))),
            vec![1, 3, 5]
        );
    }

    #[test]
    fn a_row_without_spread_keeps_everything() {
        let a = vec![1.0; 12];
        assert_eq!(
            candidate_pairs(&a, 3, 4, &live(1, 2, 0.0)),
            (0..12).collect::<Vec<_>>()
        );
    }

    #[test]
    fn every_robot_object_keeps_its_best_human_objects() {
        // 3 x 3, rows prefer column 0; column 2 is nobody's favourite but
        // keeps its best row (row 2).
        let a = [0.9, 0.5, 0.1, 0.9, 0.6, 0.2, 0.8, 0.3, 0.4];
        let pairs = candidate_pairs(&a, 3, 3, &live(1, 1, 0.0));
        assert!(pairs.contains(&(2 * 3 + 2)), "{pairs:?}");
        assert!(pairs.contains(&4), "{pairs:?}"); // (1, 1)
        assert!(pairs.iter().all(|&k| k < 9));
    }
}
