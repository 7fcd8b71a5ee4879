//! Draws used throughout the generator. Every helper consumes the same
//! number of random values whatever its parameters (a zero standard
//! deviation still draws), so changing one noise knob leaves every other
//! draw of a scene unchanged: a noise sweep compares like with like.

use std::f64::consts::TAU;

use rand::{Rng, RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;

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

/// What a keyed stream is for; each purpose draws from its own streams.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u64)]
pub(crate) enum Purpose {
    /// A live world's layout, cameras, track ids and motions.
    Setup = 1,
    /// One object's absences and put-backs.
    Presence = 2,
    /// One camera's measurement errors.
    Frame = 3,
    /// The person's choice of target and pointing error.
    Gesture = 4,
    /// Views with nothing in common (`unrelated`).
    Unrelated = 5,
}

/// A random stream that depends only on `seed`, `purpose`, `key` and
/// `index`: whoever asks for the same four gets the same values, in any
/// process, in any order.
pub(crate) fn keyed(seed: u64, purpose: Purpose, key: u64, index: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(mix(seed ^ mix(purpose as u64 ^ mix(key))));
    rng.set_stream(index);
    rng
}

/// SplitMix64, the stream of the rigid scenes (`rigid_scene`), which must
/// draw exactly as they always have; a [`RngCore`] so that the helpers
/// above draw from it as from ChaCha8.
#[derive(Debug, Clone)]
pub(crate) struct SplitMix(u64);

impl SplitMix {
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }
}

impl RngCore for SplitMix {
    fn next_u64(&mut self) -> u64 {
        let out = mix(self.0);
        self.0 = self.0.wrapping_add(GAMMA);
        out
    }

    fn next_u32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }

    fn fill_bytes(&mut self, dst: &mut [u8]) {
        rand::rand_core::impls::fill_bytes_via_next(self, dst);
    }
}

/// splitmix64's increment.
const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// splitmix64's finaliser: nearby inputs give unrelated outputs.
fn mix(x: u64) -> u64 {
    let mut z = x.wrapping_add(GAMMA);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
