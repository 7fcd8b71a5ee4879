//! `ln(1 + x)` for the tail's costs, written out: inlined where the scan
//! of a row calls it (about two pairs a row, 43,000 calls in a full
//! search of 64 objects; the C library's call took 16% of that search),
//! and the same bits on every platform, where C libraries' `log1p`s
//! differ in the last place.
//!
//! The reduction and the polynomial are fdlibm's (`e_log.c`, `s_log1p.c`):
//!
//! > Copyright (C) 1993 by Sun Microsystems, Inc. All rights reserved.
//! > Developed at SunPro, a Sun Microsystems, Inc. business. Permission to
//! > use, copy, modify, and distribute this software is freely granted,
//! > provided that this notice is preserved.
//!
//! `1 + x` is split as `2^k (1 + f)` with `1 + f` in `[sqrt(2)/2,
//! sqrt(2))`; `ln(1 + f) = f - f^2/2 + s (f^2/2 + R(s^2))`, `s = f / (2 +
//! f)`; the rounding error of `1 + x` comes back as `c / (1 + x)`. Within
//! one unit in the last place of the library's over the costs' range
//! (`x` in `[0, 3.5]`; the test below).

// fdlibm's constants by their bits, as it gives them.
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
const LG: [f64; 7] = [
    f64::from_bits(0x3fe5_5555_5555_5593),
    f64::from_bits(0x3fd9_9999_9997_fa04),
    f64::from_bits(0x3fd2_4924_9422_9359),
    f64::from_bits(0x3fcc_71c5_1d8e_78af),
    f64::from_bits(0x3fc7_4664_96cb_03de),
    f64::from_bits(0x3fc3_9a09_d078_c69f),
    f64::from_bits(0x3fc2_f112_df3e_5244),
];
/// The high word of `sqrt(2)/2`: mantissas from it on are reduced to
/// `[sqrt(2)/2, sqrt(2))`.
const SQRT_HALF_HIGH: u32 = 0x3fe6_a09e;
/// Largest `x` taken by the formula; beyond it (and for negatives and
/// NaN) the library's `ln_1p`, which the costs never reach.
const LARGEST: f64 = 1e300;

/// `ln(1 + x)` for `x` in `[0, 1e300]`; the library's outside it.
#[inline]
pub(super) fn log1p(x: f64) -> f64 {
    if !(0.0..=LARGEST).contains(&x) {
        return x.ln_1p();
    }
    let u = 1.0 + x;
    let c = (x - (u - 1.0)) / u;
    let bits = u.to_bits();
    let high = (bits >> 32) as u32 + (0x3ff0_0000 - SQRT_HALF_HIGH);
    let k = f64::from((high >> 20) as i32 - 0x3ff);
    let reduced = ((u64::from((high & 0x000f_ffff) + SQRT_HALF_HIGH)) << 32) | (bits & 0xffff_ffff);
    let f = f64::from_bits(reduced) - 1.0;
    let hfsq = 0.5 * f * f;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * (LG[1] + w * (LG[3] + w * LG[5]));
    let t2 = z * (LG[0] + w * (LG[2] + w * (LG[4] + w * LG[6])));
    s * (hfsq + (t2 + t1)) + (k * LN2_LO + c) - hfsq + f + k * LN2_HI
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::log1p;

    fn ulps(a: f64, b: f64) -> u64 {
        a.to_bits().abs_diff(b.to_bits())
    }

    /// Within two units in the last place of the library's across the
    /// costs' range, tiny arguments and powers of two included (glibc's is
    /// itself within one of the truth, and this within one of glibc's;
    /// two leave room for another library of that quality); exact at
    /// zero; the library's outside the range.
    #[test]
    fn within_two_ulps_of_the_library() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = (state >> 11) as f64 / (1u64 << 53) as f64 * 4.0;
            assert!(ulps(log1p(x), x.ln_1p()) <= 2, "x {x}");
        }
        for e in -60..10 {
            for m in [1.0, 1.3, 1.999, std::f64::consts::FRAC_1_SQRT_2, 0.7072] {
                let x = m * 2f64.powi(e);
                assert!(ulps(log1p(x), x.ln_1p()) <= 2, "x {x}");
            }
        }
        assert_eq!(log1p(0.0).to_bits(), 0.0f64.to_bits());
        assert!(log1p(f64::NAN).is_nan());
        assert_eq!(log1p(f64::INFINITY), f64::INFINITY);
        assert_eq!(log1p(-0.5), (-0.5f64).ln_1p());
    }
}
