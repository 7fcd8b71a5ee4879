//! `exp(-t)` for the live tier's kernel tables: a branch-free polynomial
//! the compiler can vectorise, instead of one libm call per entry.

const LOG2_E: f64 = std::f64::consts::LOG2_E;
/// ln 2 split in two so that `k * LN2_HI` is exact for |k| < 2^11.
const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
/// Beyond this, `exp(-t)` is below the smallest normal f64: 0.
const CUTOFF: f64 = 708.0;
/// 1.5 * 2^52: adding and subtracting it rounds to the nearest integer
/// without a call (x86-64's baseline has no rounding instruction), and the
/// sum's low bits hold that integer.
const ROUNDER: f64 = 6_755_399_441_055_744.0;

/// `exp(-t)` for `t >= 0` (NaN and `t > 708` give 0), within 2e-15 of
/// the exact value relative to it.
#[inline(always)]
pub fn exp_neg(t: f64) -> f64 {
    let (r, scale) = reduce(t);
    // Taylor series of exp(r) for |r| <= ln2 / 2, to r^13.
    scaled(t, horner::<false>(&TAYLOR, r), scale)
}

/// `exp(-t)` for values to be stored as f32 (the exact tier's kernel
/// table): the same reduction as [`exp_neg`] with the Taylor series cut at
/// r^9, whose remainder is below 1e-11 relative, far under f32's rounding
/// (6e-8). NaN and `t > 708` give 0. With fused multiply-adds in the series
/// when `FMA`, only for code compiled with the `fma` target feature
/// (elsewhere `mul_add` is a library call).
#[inline(always)]
pub fn exp_neg_single_with<const FMA: bool>(t: f64) -> f64 {
    let (r, scale) = reduce(t);
    scaled(t, horner::<FMA>(&TAYLOR[TAYLOR.len() - 10..], r), scale)
}

/// The Taylor coefficients of exp, 1 / k! from k = 13 down to 0.
const TAYLOR: [f64; 14] = [
    1.0 / 6_227_020_800.0,
    1.0 / 479_001_600.0,
    1.0 / 39_916_800.0,
    1.0 / 3_628_800.0,
    1.0 / 362_880.0,
    1.0 / 40_320.0,
    1.0 / 5_040.0,
    1.0 / 720.0,
    1.0 / 120.0,
    1.0 / 24.0,
    1.0 / 6.0,
    0.5,
    1.0,
    1.0,
];

/// The polynomial with `coefficients` (highest power first) at `r`, in
/// Horner form; with fused multiply-adds when `FMA`.
#[inline(always)]
fn horner<const FMA: bool>(coefficients: &[f64], r: f64) -> f64 {
    let (first, rest) = coefficients
        .split_first()
        .map_or((0.0, &[][..]), |(f, r)| (*f, r));
    rest.iter()
        .fold(first, |p, &c| if FMA { p.mul_add(r, c) } else { p * r + c })
}

/// `-t = k ln2 + r` with `|r| <= ln2 / 2`: returns `r` and `2^k`, so that
/// `exp(-t) = exp(r) 2^k`. `t` is clamped to `[0, 708]` first.
#[inline(always)]
fn reduce(t: f64) -> (f64, f64) {
    let x = -t.clamp(0.0, CUTOFF);
    let shifted = x * LOG2_E + ROUNDER;
    let k = shifted - ROUNDER;
    let k_bits = shifted.to_bits().wrapping_sub(ROUNDER.to_bits());
    let r = (x - k * LN2_HI) - k * LN2_LO;
    // 2^k by building the exponent bits; k is in [-1022, 0].
    let scale = f64::from_bits(k_bits.wrapping_add(1023) << 52);
    (r, scale)
}

/// `exp(r) 2^k` from the series value `p` of `exp(r)`, and 0 for NaN and
/// for `t` beyond the cutoff (where the clamp kept the value finite).
#[inline(always)]
fn scaled(t: f64, p: f64, scale: f64) -> f64 {
    let value = p * scale;
    if t > CUTOFF || t.is_nan() { 0.0 } else { value }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_libm_to_a_few_ulps() {
        let mut worst: f64 = 0.0;
        for k in 0..200_000 {
            let t = k as f64 * 0.0035;
            let (got, want) = (exp_neg(t), (-t).exp());
            if want > 0.0 {
                worst = worst.max(((got - want) / want).abs());
            }
        }
        assert!(worst < 2e-15, "relative error {worst}");
        assert_eq!(exp_neg(0.0), 1.0);
        assert_eq!(exp_neg(800.0), 0.0);
        assert_eq!(exp_neg(f64::NAN), 0.0);
        assert_eq!(exp_neg(f64::INFINITY), 0.0);
    }

    #[test]
    fn single_precision_variant_is_within_1e_11() {
        let mut worst: f64 = 0.0;
        for k in 0..200_000 {
            let t = k as f64 * 0.0035;
            let (got, want) = (exp_neg_single_with::<false>(t), (-t).exp());
            if want > 0.0 {
                worst = worst.max(((got - want) / want).abs());
            }
        }
        assert!(worst < 1e-11, "relative error {worst}");
        assert_eq!(exp_neg_single_with::<false>(0.0), 1.0);
        assert_eq!(exp_neg_single_with::<false>(800.0), 0.0);
        assert_eq!(exp_neg_single_with::<false>(f64::NAN), 0.0);
        assert_eq!(exp_neg_single_with::<false>(f64::INFINITY), 0.0);
    }
}
