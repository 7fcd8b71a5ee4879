use crate::{PairAffinity, SpatialAffinity};

/// The spatial affinity a method multiplies by: over every pair (exact
/// tier) or over candidate pairs only (live tier).
#[derive(Debug, Clone)]
pub enum SpatialTerm {
    Edges(SpatialAffinity),
    Pairs(PairAffinity),
}

impl SpatialTerm {
    /// `out = S x`.
    pub fn mul(&self, x: &[f64], out: &mut [f64]) {
        match self {
            SpatialTerm::Edges(s) => s.mul(x, out),
            SpatialTerm::Pairs(s) => s.mul(x, out),
        }
    }

    /// The largest row sum of S, by which `sm`, `rrwm` and `paper` scale
    /// their walk. Every one of them normalises the scaled vector
    /// afterwards, so the scale cancels: the live tier skips the product
    /// that would compute it and says 1.
    pub fn max_row_sum(&self) -> f64 {
        match self {
            SpatialTerm::Edges(s) => s.row_sums().into_iter().fold(f64::NEG_INFINITY, f64::max),
            SpatialTerm::Pairs(_) => 1.0,
        }
    }

    /// Number of human and robot objects.
    pub fn shape(&self) -> (usize, usize) {
        match self {
            SpatialTerm::Edges(s) => s.shape(),
            SpatialTerm::Pairs(s) => s.shape(),
        }
    }
}
