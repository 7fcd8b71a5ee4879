/// Early stop of the live tier: the assignment a solve would give has
/// stopped changing. Tracks every row's best column, which is what the
/// Hungarian discretisation starts from; no work when disabled.
pub(super) struct Stability {
    needed: Option<usize>,
    m: usize,
    best: Vec<usize>,
    stable: usize,
}

impl Stability {
    /// `warm`: the warm start, whose assignment counts as the one before
    /// the first iteration (a cold start has none).
    pub(super) fn new(n: usize, m: usize, needed: Option<usize>, warm: Option<&[f64]>) -> Self {
        let mut stability = Self {
            needed,
            m,
            best: if needed.is_some() {
                vec![usize::MAX; n]
            } else {
                Vec::new()
            },
            stable: 0,
        };
        if let Some(w) = warm.filter(|w| w.len() == n * m) {
            stability.settled(w);
            stability.stable = 0;
        }
        stability
    }

    /// Whether every row's best column in `x` has now been the same for the
    /// required number of consecutive iterations.
    pub(super) fn settled(&mut self, x: &[f64]) -> bool {
        let Some(needed) = self.needed else {
            return false;
        };
        let mut changed = false;
        for (row, best) in x.chunks_exact(self.m).zip(self.best.iter_mut()) {
            let top = row
                .iter()
                .enumerate()
                .fold(
                    (0, f64::NEG_INFINITY),
                    |acc, (a, &v)| {
                        if v > acc.1 { (a, v) } else { acc }
                    },
                )
                .0;
            changed |= top != *best;
            *best = top;
        }
        self.stable = if changed { 0 } else { self.stable + 1 };
        self.stable >= needed
    }
}

/// The start vector: `warm` scaled to sum 1 when it is a usable
/// distribution, else uniform.
pub(super) fn start(warm: Option<&[f64]>, len: usize) -> Vec<f64> {
    if let Some(w) = warm {
        let sum: f64 = w.iter().sum();
        if w.len() == len && sum > 0.0 && sum.is_finite() && w.iter().all(|&v| v >= 0.0) {
            return w.iter().map(|v| v / sum).collect();
        }
    }
    super::vector::uniform(len)
}
