//! Round trips of one kind, in microseconds, with the one percentile
//! definition (vref_measure: nearest rank).

use std::time::Duration;

/// Round trips of one kind, microseconds.
#[derive(Debug, Default, Clone)]
pub struct Samples(Vec<f64>);

impl Samples {
    pub fn push(&mut self, d: Duration) {
        self.0.push(d.as_secs_f64() * 1e6);
    }

    pub fn count(&self) -> usize {
        self.0.len()
    }

    /// Nearest-rank percentile (vref_measure's one definition); `None`
    /// without samples.
    pub fn percentile(&self, q: f64) -> Option<f64> {
        vref_measure::percentile_of(&self.0, q)
    }

    /// One line of a round-trip table (`ROW_HEADER`): name, count, p50,
    /// p99, p99.9 in microseconds.
    pub fn row(&self, name: &str) -> Vec<String> {
        let cell = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.1}"));
        vec![
            name.to_owned(),
            self.count().to_string(),
            cell(self.percentile(0.5)),
            cell(self.percentile(0.99)),
            cell(self.percentile(0.999)),
        ]
    }
}

/// The columns of `Samples::row`.
pub const ROW_HEADER: [&str; 5] = ["round trip", "count", "p50 us", "p99 us", "p99.9 us"];

/// Microseconds to one decimal, `null` without samples.
pub fn us(value: Option<f64>) -> serde_json::Value {
    value.map_or(serde_json::Value::Null, |v| {
        serde_json::json!((v * 10.0).round() / 10.0)
    })
}

/// `a / b` to three decimals, `None` without both (or with `b` zero).
pub fn ratio(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) if b > 0.0 => Some((a / b * 1000.0).round() / 1000.0),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_are_nearest_rank_and_none_when_empty() {
        let mut s = Samples::default();
        assert_eq!(s.percentile(0.5), None);
        for v in [5, 1, 4, 2, 3] {
            s.push(Duration::from_micros(v));
        }
        assert_eq!(s.percentile(0.5), Some(3.0));
        assert_eq!(s.percentile(0.99), Some(5.0));
        assert_eq!(s.percentile(0.0), Some(1.0));
    }

    #[test]
    fn ratio_is_a_over_b_and_none_without_both() {
        assert_eq!(ratio(Some(130.0), Some(100.0)), Some(1.3));
        assert_eq!(ratio(None, Some(100.0)), None);
        assert_eq!(ratio(Some(1.0), Some(0.0)), None);
    }
}
