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

    /// A double-double: `hi + lo`, `|lo|` at most half an ulp of `hi`.
    #[derive(Clone, Copy)]
    struct Dd(f64, f64);

    /// `a + b` exactly, as a double-double (Knuth's two-sum).
    fn two_sum(a: f64, b: f64) -> Dd {
        let s = a + b;
        let v = s - a;
        Dd(s, (a - (s - v)) + (b - v))
    }

    fn add(a: Dd, b: Dd) -> Dd {
        let s = two_sum(a.0, b.0);
        let t = two_sum(a.1, b.1);
        let u = two_sum(s.0, s.1 + t.0);
        two_sum(u.0, u.1 + t.1)
    }

    fn mul(a: Dd, b: Dd) -> Dd {
        let p = a.0 * b.0;
        // The product's rounding error, exact by a fused multiply-add.
        let e = a.0.mul_add(b.0, -p);
        two_sum(p, e + (a.0 * b.1 + a.1 * b.0))
    }

    fn div(a: Dd, b: Dd) -> Dd {
        let q1 = a.0 / b.0;
        let r = add(a, mul(Dd(-q1, 0.0), b));
        let q2 = r.0 / b.0;
        let r = add(r, mul(Dd(-q2, 0.0), b));
        let q3 = r.0 / b.0;
        add(two_sum(q1, q2), Dd(q3, 0.0))
    }

    /// `ln(1 + x)` correctly rounded (but for ties, which a random
    /// argument does not meet): `2 atanh(s)`, `s = x / (2 + x)`, summed
    /// in double-doubles until a term is below `2^-110` of the sum (for
    /// `x` in `[0, 4]`, `s <= 2/3`).
    fn reference(x: f64) -> f64 {
        let s = div(Dd(x, 0.0), two_sum(2.0, x));
        let s2 = mul(s, s);
        let (mut power, mut sum) = (s, s);
        for k in 1.. {
            power = mul(power, s2);
            let term = div(power, Dd(f64::from(2 * k + 1), 0.0));
            sum = add(sum, term);
            if term.0.abs() < sum.0.abs() * 2f64.powi(-110) {
                break;
            }
        }
        let doubled = add(sum, sum);
        doubled.0 + doubled.1
    }

    /// Within one unit in the last place of the true value (fdlibm's
    /// bound for its `log1p`) across the costs' range, tiny arguments
    /// and powers of two included; exact at zero; the library's outside
    /// the range.
    #[test]
    fn within_one_ulp_of_the_true_value() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut exact = 0;
        for _ in 0..100_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = (state >> 11) as f64 / (1u64 << 53) as f64 * 4.0;
            let (got, truth) = (log1p(x), reference(x));
            assert!(ulps(got, truth) <= 1, "x {x}: {got} against {truth}");
            exact += usize::from(got == truth);
        }
        // An approximation off by one everywhere would pass the bound;
        // this one is mostly correctly rounded.
        assert!(exact > 50_000, "{exact} of 100000 correctly rounded");
        for e in -60..3 {
            for m in [1.0, 1.3, 1.999, std::f64::consts::FRAC_1_SQRT_2, 0.7072] {
                let x = m * 2f64.powi(e);
                assert!(ulps(log1p(x), reference(x)) <= 1, "x {x}");
            }
        }
        assert_eq!(log1p(0.0).to_bits(), 0.0f64.to_bits());
        assert!(log1p(f64::NAN).is_nan());
        assert_eq!(log1p(f64::INFINITY), f64::INFINITY);
        assert_eq!(log1p(-0.5), (-0.5f64).ln_1p());
    }

    /// The reference itself, at values known to many places.
    #[test]
    fn the_reference_is_right() {
        assert_eq!(reference(1.0), std::f64::consts::LN_2);
        assert_eq!(reference(std::f64::consts::E - 1.0), 1.0);
        let tiny = 1e-20;
        assert_eq!(reference(tiny), tiny);
    }
}
