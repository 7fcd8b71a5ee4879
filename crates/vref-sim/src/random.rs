//! Draws used throughout the generator. Every helper consumes the same
//! number of random values whatever its parameters (a zero standard
//! deviation still draws), so changing one noise knob leaves every other
//! draw of a scene unchanged: a noise sweep compares like with like.

use std::f64::consts::TAU;

use rand::Rng;

/// A standard normal value (Box-Muller, one of the pair).
pub(crate) fn standard_normal<R: Rng>(rng: &mut R) -> f64 {
    // 1 - [0, 1) is (0, 1]: the logarithm stays finite.
    let u1 = 1.0 - rng.random::<f64>();
    let u2 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
}

pub(crate) fn normal<R: Rng>(rng: &mut R, sigma: f64) -> f64 {
    sigma * standard_normal(rng)
}

/// Uniform in `[lo, hi]`.
pub(crate) fn uniform<R: Rng>(rng: &mut R, [lo, hi]: [f64; 2]) -> f64 {
    lo + (hi - lo) * rng.random::<f64>()
}

/// Uniform integer in `lo..=hi`.
pub(crate) fn count<R: Rng>(rng: &mut R, [lo, hi]: [usize; 2]) -> usize {
    rng.random_range(lo..=hi)
}
