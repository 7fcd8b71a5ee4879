//! The one percentile definition: nearest rank. The p-th percentile
//! (`q` = p/100 in 0..=1) of n values is the value at rank ceil(q·n) in
//! ascending order, counting from 1, and at least rank 1: p50 of 1..=1000
//! is 500, p99 is 990, p99.9 is 999, p0 is the smallest value and p100
//! the largest. It is always one of the values, never an interpolation.
//! `clients/python/src/vref_client/measure.py` implements the same.

/// The 1-based rank of quantile `q` among `n` values: ceil(q·n), clamped
/// to 1..=n; 0 only when `n` is 0. A product within 1e-9 of a whole
/// number counts as that number, so that 0.07·100 is rank 7, not 8, in
/// spite of floating point. A `q` outside 0..=1 (or NaN) is clamped.
pub fn nearest_rank(q: f64, n: usize) -> usize {
    if n == 0 {
        return 0;
    }
    let q = if q.is_nan() { 0.0 } else { q.clamp(0.0, 1.0) };
    let x = q * n as f64;
    let whole = x.round();
    let x = if (x - whole).abs() < 1e-9 { whole } else { x };
    // x is in 0..=n, so the cast neither wraps nor truncates a sign.
    (x.ceil() as usize).clamp(1, n)
}

/// Quantile `q` (0..=1) of values already sorted ascending; `None`
/// without values.
pub fn percentile<T: Copy>(sorted: &[T], q: f64) -> Option<T> {
    match nearest_rank(q, sorted.len()) {
        0 => None,
        rank => sorted.get(rank - 1).copied(),
    }
}

/// Quantile `q` (0..=1) of values in any order (sorted here, NaN last);
/// `None` without values.
pub fn percentile_of<T: Copy + PartialOrd>(values: &[T], q: f64) -> Option<T> {
    let mut sorted = values.to_vec();
    sorted.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Greater));
    percentile(&sorted, q)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn p50_of_1_to_1000_is_500() {
        let v: Vec<u64> = (1..=1000).collect();
        assert_eq!(percentile(&v, 0.5), Some(500));
        assert_eq!(percentile(&v, 0.99), Some(990));
        assert_eq!(percentile(&v, 0.999), Some(999));
        assert_eq!(percentile(&v, 1.0), Some(1000));
        assert_eq!(percentile(&v, 0.0), Some(1));
    }

    #[test]
    fn small_sets_and_empty() {
        assert_eq!(percentile::<u64>(&[], 0.5), None);
        assert_eq!(percentile(&[7.0], 0.99), Some(7.0));
        assert_eq!(percentile(&[1, 2], 0.5), Some(1));
        assert_eq!(percentile(&[1, 2, 3, 4, 5], 0.5), Some(3));
        assert_eq!(percentile(&[1, 2, 3, 4, 5], 0.99), Some(5));
        let hundred: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(&hundred, 0.5), Some(50.0));
        assert_eq!(percentile(&hundred, 0.99), Some(99.0));
    }

    #[test]
    fn floating_point_products_do_not_skip_a_rank() {
        // 0.07 * 100 is 7.000000000000001 in f64.
        assert_eq!(nearest_rank(0.07, 100), 7);
        assert_eq!(nearest_rank(0.29, 100), 29);
        assert_eq!(nearest_rank(0.999, 1000), 999);
        assert_eq!(nearest_rank(0.5, 3), 2);
        assert_eq!(nearest_rank(0.5, 0), 0);
        assert_eq!(nearest_rank(f64::NAN, 10), 1);
        assert_eq!(nearest_rank(2.0, 10), 10);
    }

    #[test]
    fn unsorted_input_is_sorted_first() {
        assert_eq!(percentile_of(&[5, 1, 4, 2, 3], 0.5), Some(3));
        assert_eq!(percentile_of(&[3.0, 1.0, 2.0], 0.0), Some(1.0));
        assert_eq!(percentile_of::<f64>(&[], 0.5), None);
    }
}
