//! Objects that moved between the views. One motion explains both views,
//! so an object moved between them has no partner under it; where its
//! look singles out one robot object that the motion left unpaired too,
//! that is its likeliest partner, and the robot may confirm it. Such a
//! partner rests on appearance alone, so it is never sure.

/// The pairs `(row, column)` of objects that `assignment` leaves without
/// a partner on both sides and whose looks single each other out: the
/// column is the row's most alike (`appearance`, row-major `n x m`) by at
/// least `gap` over every other column, and the row is alike to it by at
/// least `gap` over every other row. None for a `gap` that is not finite.
pub(super) fn partners_by_look(
    appearance: &[f64],
    n: usize,
    m: usize,
    assignment: &[Option<usize>],
    gap: f64,
) -> Vec<(usize, usize)> {
    if !gap.is_finite() || m == 0 {
        return Vec::new();
    }
    let mut taken = vec![false; m];
    for &j in assignment.iter().flatten() {
        taken[j] = true;
    }
    let mut pairs = Vec::new();
    for (i, row) in appearance.chunks(m).enumerate().take(n) {
        if assignment.get(i).is_none_or(Option::is_some) {
            continue;
        }
        let Some(j) = (0..m).max_by(|&a, &b| row[a].total_cmp(&row[b]).then(b.cmp(&a))) else {
            continue;
        };
        let unique_in_row = (0..m).all(|k| k == j || row[k] <= row[j] - gap);
        let unique_in_column = (0..n).all(|k| k == i || appearance[k * m + j] <= row[j] - gap);
        if !taken[j] && unique_in_row && unique_in_column {
            pairs.push((i, j));
        }
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::partners_by_look;

    /// Row 2 and column 2 are both unpaired and single each other out;
    /// row 3's best column is taken; a look-alike in the row or in the
    /// column, or an infinite gap, pairs nothing.
    #[test]
    fn only_unpaired_objects_that_single_each_other_out_are_paired() {
        #[rustfmt::skip]
        let a = [
            0.9, 0.1, 0.1,
            0.1, 0.9, 0.1,
            0.1, 0.2, 0.9,
            0.8, 0.1, 0.1,
        ];
        let assignment = [Some(0), Some(1), None, None];
        assert_eq!(partners_by_look(&a, 4, 3, &assignment, 0.3), vec![(2, 2)]);
        assert_eq!(partners_by_look(&a, 4, 3, &assignment, 0.75), vec![]);
        assert_eq!(
            partners_by_look(&a, 4, 3, &assignment, f64::INFINITY),
            vec![]
        );
        let mut alike_in_row = a;
        alike_in_row[7] = 0.7;
        assert_eq!(
            partners_by_look(&alike_in_row, 4, 3, &assignment, 0.3),
            vec![]
        );
        let mut alike_in_column = a;
        alike_in_column[11] = 0.7;
        assert_eq!(
            partners_by_look(&alike_in_column, 4, 3, &assignment, 0.3),
            vec![]
        );
        let taken = [Some(0), Some(1), None, Some(2)];
        assert_eq!(partners_by_look(&a, 4, 3, &taken, 0.3), vec![]);
    }
}
