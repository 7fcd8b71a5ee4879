//! The dot products of the appearance affinities, one human object
//! against every robot object at once.

use super::view::Tracked;

/// The robot objects' features by dimension (`dims x m`, widened to f64),
/// so that a human feature's sums over every robot object run side by
/// side, a lane each, instead of one sum after another, each waiting on
/// its own last addition.
pub(super) struct Columns {
    dims: usize,
    m: usize,
    values: Vec<f64>,
}

impl Columns {
    /// `None` without robot objects or where their features differ in
    /// length (each pair then sums its own).
    pub(super) fn of(robot: &[Tracked]) -> Option<Self> {
        let dims = robot.first()?.feature.len();
        if robot.iter().any(|o| o.feature.len() != dims) {
            return None;
        }
        let m = robot.len();
        let mut values = vec![0.0; dims * m];
        for (a, o) in robot.iter().enumerate() {
            for (d, &v) in o.feature.iter().enumerate() {
                values[d * m + a] = f64::from(v);
            }
        }
        Some(Self { dims, m, values })
    }

    /// `feature`'s dot product with every robot object's into `out`, each
    /// to the bit [`crate::appearance::dot`]'s: the same products added in the same
    /// order from the same start. `None` where `feature`'s length is not
    /// the robot features'.
    pub(super) fn dots<'o>(&self, feature: &[f32], out: &'o mut Vec<f64>) -> Option<&'o [f64]> {
        if feature.len() != self.dims {
            return None;
        }
        out.clear();
        out.resize(self.m, empty_sum());
        for (&u, column) in feature.iter().zip(self.values.chunks_exact(self.m)) {
            let u = f64::from(u);
            for (sum, &v) in out.iter_mut().zip(column) {
                *sum += u * v;
            }
        }
        Some(out)
    }
}

/// Where `Iterator::sum` starts (the sign of a zero sum depends on it).
fn empty_sum() -> f64 {
    std::iter::empty::<f64>().sum()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::Columns;
    use crate::appearance::dot as pair_dot;
    use crate::engine::view::Tracked;

    fn object(feature: Vec<f32>) -> Tracked {
        Tracked {
            id: 0,
            position: [0.0; 3],
            sigma: [0.0; 3],
            norm: 1.0,
            feature,
        }
    }

    /// Side by side, every sum has the bits of the pair's own, on values
    /// whose rounding depends on the order (and signed zeros); features
    /// of another length are refused.
    #[test]
    fn the_sums_side_by_side_are_each_pairs_own() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            ((state >> 40) as f32 / (1u32 << 24) as f32 - 0.5) * 10f32.powi((state % 7) as i32 - 3)
        };
        for (dims, m) in [(1, 1), (3, 7), (48, 64), (33, 5)] {
            let robot: Vec<Tracked> = (0..m)
                .map(|_| object((0..dims).map(|_| next()).collect()))
                .collect();
            let columns = Columns::of(&robot).unwrap();
            let mut out = Vec::new();
            for _ in 0..5 {
                let human: Vec<f32> = (0..dims).map(|_| next()).collect();
                let dots = columns.dots(&human, &mut out).unwrap().to_vec();
                for (a, o) in robot.iter().enumerate() {
                    assert_eq!(dots[a].to_bits(), pair_dot(&human, &o.feature).to_bits());
                }
                assert!(columns.dots(&human[1..], &mut out).is_none());
            }
        }
        let zeros = vec![
            object(vec![-0.0, 0.0]),
            object(vec![0.0, -0.0]),
            object(vec![0.0, 0.0]),
        ];
        let columns = Columns::of(&zeros).unwrap();
        let mut out = Vec::new();
        let dots = columns.dots(&[-0.0, -0.0], &mut out).unwrap().to_vec();
        for (d, o) in dots.iter().zip(&zeros) {
            assert_eq!(d.to_bits(), pair_dot(&[-0.0, -0.0], &o.feature).to_bits());
        }
        let ragged = vec![object(vec![1.0]), object(vec![1.0, 2.0])];
        assert!(Columns::of(&ragged).is_none());
    }
}
