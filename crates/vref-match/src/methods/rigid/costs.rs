//! The cost of a pair under a motion: appearance and the residual in units
//! of its expected error (the depth-error ray model, stated errors, or one
//! isotropic scale).

use nalgebra::Point3;

use super::RigidParams;
use super::log1p::log1p;
use crate::Problem;
use crate::RigidMotion;

/// How far below a pair's cost its bound in [`Costs::cheapest_two`] is
/// kept, so that rounding never lifts the bound above the cost.
const BOUND_MARGIN: f64 = 1e-9;

/// The per-pair costs of one motion (or of appearance alone).
pub(super) struct Costs<'a> {
    pub(super) problem: &'a Problem,
    pub(super) log_g: &'a [f64],
    inv_two_sigma2: f64,
    /// Per pair, when the sensors state position errors: `1 / (2 s^2)`
    /// with `s^2 = sigma^2 + var_i + var_j`. The residual is weighed in
    /// units of its own expected error (a Mahalanobis gate, as trackers
    /// gate detections), without the Gaussian's normalisation: with it, an
    /// object far from the camera would cost more than "no partner" even
    /// at its exact place (on the feeds' world of 64 objects it left 98% of
    /// the objects unmatched).
    pub(super) stated: Option<Vec<f64>>,
    /// Robot positions by coordinate, so that a row of costs is one
    /// vectorisable pass (the search computes thousands of rows).
    robot_xyz: [Vec<f64>; 3],
    pub(super) rays: Option<Rays>,
    /// The residual scale of a typical pair.
    pub(super) typical: f64,
    /// Per pair, the half squared length below which its cost may be
    /// under `limits_for` ([`limit`]): the search's rows ask for pairs
    /// below "no partner", thousands of times. Solved at the first such
    /// row (the chance views' costs never ask).
    limits: std::cell::OnceCell<Vec<f64>>,
    limits_for: f64,
}

/// Each object's ray from its camera and depth variance along it.
#[derive(Clone)]
pub(super) struct Rays {
    /// Unit rays of the human objects (human frame) and their variances.
    pub(super) human: Vec<(nalgebra::Vector3<f64>, f64)>,
    /// Robot rays by coordinate, and their variances.
    pub(super) robot_u: [Vec<f64>; 3],
    pub(super) robot_var: Vec<f64>,
    /// The depth variances' shapes, which the [`Noise`] multipliers scale:
    /// the squared range where the error is assumed, the stated variance
    /// where it is stated.
    pub(super) human_base: Vec<f64>,
    pub(super) robot_base: Vec<f64>,
    /// Lateral variance (sigma squared).
    pub(super) lateral: f64,
    /// What every row's pass is computed with, set with the scales: `1 /
    /// lateral`, and each human object's `h / (lateral + h)` (two
    /// divisions a row saved, thousands of rows a search).
    inv_lateral: f64,
    alpha: Vec<f64>,
    /// The scales in force.
    pub(super) noise: Noise,
    /// Heavy tails: a squared residual `d^2` costs `tail / 2 ln(1 + d^2 /
    /// tail)` instead of `d^2 / 2` (0: the Gaussian's).
    pub(super) tail: f64,
    /// Half squared lengths whose tailed cost reaches "no partner".
    gate: f64,
    /// Whether the depth variances are `depth_error`'s assumption rather
    /// than the sensors' statement.
    pub(super) assumed: bool,
}

/// The three scales of the ray model: the lateral variance, and the
/// multipliers of each camera's depth variances (their shapes, in
/// [`Rays`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Noise {
    pub(super) lateral: f64,
    pub(super) robot: f64,
    pub(super) human: f64,
}

impl Rays {
    /// The rays of views in front of their cameras (every z > 0): their
    /// variance along the ray is the stated error where the sensors state
    /// one (all of it: an RGB-D camera's depth error dominates and lies
    /// along the ray), else `depth_error` times the range, squared. `None`
    /// for other views or when neither applies.
    fn of(
        problem: &Problem,
        variances: &[Vec<f64>; 2],
        rp: &RigidParams,
        lateral_sigma: f64,
    ) -> Option<Self> {
        let in_front = |ps: &[Point3<f64>]| ps.iter().all(|p| p.z > 0.0);
        if !(in_front(&problem.human_positions) && in_front(&problem.robot_positions)) {
            return None;
        }
        let stated = rp.stated_errors && has_stated_errors(problem);
        if !(stated || rp.depth_error > 0.0) {
            return None;
        }
        let rays = |points: &[Point3<f64>], variances: &[f64]| -> Vec<_> {
            points
                .iter()
                .enumerate()
                .map(|(k, p)| {
                    let range = p.coords.norm();
                    let base = if stated {
                        // The mean over the axes times three: the total.
                        3.0 * variance(variances, k)
                    } else {
                        range * range
                    };
                    (p.coords / range, base)
                })
                .collect()
        };
        let human = rays(&problem.human_positions, &variances[0]);
        let robot = rays(&problem.robot_positions, &variances[1]);
        let axis = |k: usize| robot.iter().map(|(u, _)| u[k]).collect();
        let depth = if stated { 1.0 } else { rp.depth_error.powi(2) };
        let mut rays = Self {
            human_base: human.iter().map(|(_, b)| *b).collect(),
            human,
            robot_u: [axis(0), axis(1), axis(2)],
            robot_base: robot.iter().map(|(_, b)| *b).collect(),
            robot_var: Vec::new(),
            lateral: lateral_sigma * lateral_sigma,
            inv_lateral: 0.0,
            alpha: Vec::new(),
            tail: rp.tail,
            gate: if rp.tail > 0.0 {
                0.5 * rp.tail * (2.0 * rp.unmatched_cost / rp.tail).exp_m1()
            } else {
                f64::INFINITY
            },
            noise: Noise {
                lateral: 0.0,
                robot: 0.0,
                human: 0.0,
            },
            assumed: !stated,
        };
        rays.set(Noise {
            lateral: lateral_sigma * lateral_sigma,
            robot: depth,
            human: depth,
        });
        Some(rays)
    }

    /// Takes on `noise`'s scales.
    pub(super) fn set(&mut self, noise: Noise) {
        self.lateral = noise.lateral;
        self.noise = noise;
        self.robot_var = self.robot_base.iter().map(|b| b * noise.robot).collect();
        for ((_, v), b) in self.human.iter_mut().zip(&self.human_base) {
            *v = b * noise.human;
        }
        self.inv_lateral = 1.0 / self.lateral;
        self.alpha = self
            .human
            .iter()
            .map(|(_, h)| h / (self.lateral + h))
            .collect();
    }

    /// The typical pair's residual scale.
    fn typical(&self) -> f64 {
        let human: Vec<f64> = self.human.iter().map(|(_, h)| *h).collect();
        (self.lateral + median(&human) + median(&self.robot_var)).sqrt()
    }

    /// Half the squared Mahalanobis length of residual `r` of human object
    /// `i` (ray `w` in the robot frame, `alpha` = h / (lateral + h)) against
    /// robot object `j`: the covariance is `lateral I + h w w^T + c u u^T`,
    /// inverted by Sherman-Morrison twice. (The search and the matrices
    /// compute it a row at a time, by [`Rays::half_lengths`].)
    #[cfg(test)]
    fn half_distance2(&self, r: [f64; 3], w: [f64; 3], alpha: f64, j: usize) -> f64 {
        let u = [self.robot_u[0][j], self.robot_u[1][j], self.robot_u[2][j]];
        half_mahalanobis2(r, w, alpha, u, self.robot_var[j], 1.0 / self.lateral)
    }

    /// The tailed costs of human object `i`, at `moved`, against every
    /// robot object (`xyz`: their positions by coordinate), into `out`;
    /// beyond the gate, the half squared length itself.
    fn row(
        &self,
        i: usize,
        motion: &RigidMotion,
        moved: &Point3<f64>,
        xyz: &[Vec<f64>; 3],
        out: &mut [f64],
    ) {
        self.half_lengths(i, motion, moved, xyz, out);
        if self.tail > 0.0 {
            // Beyond `gate` a pair costs more than "no partner" with or
            // without the tail; the search only asks which pairs are below
            // it, so the logarithm is spent on those alone.
            for o in out.iter_mut().filter(|o| **o < self.gate) {
                *o = self.robust(*o);
            }
        }
    }

    /// What human object `i`'s row is computed from, at `moved` under
    /// `motion`, against every robot object (`xyz`: their positions by
    /// coordinate), every slice cut to the row's length `m`.
    fn row_inputs<'s>(
        &'s self,
        i: usize,
        motion: &RigidMotion,
        moved: &Point3<f64>,
        xyz: &'s [Vec<f64>; 3],
        m: usize,
    ) -> RowInputs<'s> {
        let (w, alpha) = self.human_ray(i, &motion.rotation);
        RowInputs {
            moved: [moved.x, moved.y, moved.z],
            w,
            alpha,
            inv: self.inv_lateral,
            xyz: [&xyz[0][..m], &xyz[1][..m], &xyz[2][..m]],
            u: [
                &self.robot_u[0][..m],
                &self.robot_u[1][..m],
                &self.robot_u[2][..m],
            ],
            var: &self.robot_var[..m],
        }
    }

    /// [`Rays::half_distance2`] of human object `i`, at `moved`, against
    /// every robot object (`xyz`: their positions by coordinate), into
    /// `out`: one vectorised pass (the search computes thousands of rows).
    fn half_lengths(
        &self,
        i: usize,
        motion: &RigidMotion,
        moved: &Point3<f64>,
        xyz: &[Vec<f64>; 3],
        out: &mut [f64],
    ) {
        let row = self.row_inputs(i, motion, moved, xyz, out.len());
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::avx512() {
            #[allow(unsafe_code)]
            // SAFETY: the CPU has AVX-512F (checked just above), the only
            // requirement of a `target_feature` function.
            unsafe {
                half_lengths_avx512(&row, out);
            }
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::avx2_fma() {
            #[allow(unsafe_code)]
            // SAFETY: the CPU has AVX2 (checked just above), the only
            // requirement of a `target_feature` function.
            unsafe {
                half_lengths_avx2(&row, out);
            }
            return;
        }
        half_lengths_of(&row, out);
    }

    /// `row`'s half squared lengths into `scratch.lengths`, and in
    /// `scratch.masks` a bit per pair, set where its length is below its
    /// `limits` entry (what [`limit`] gives for its appearance): one
    /// vectorised pass without a logarithm, so that the scan that follows
    /// looks at the few pairs that may be taken, not at every pair.
    fn bounded_row(&self, row: &RowInputs<'_>, limits: &[f64], scratch: &mut RowScratch) {
        // Written by hand (the compiler left the masks scalar).
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::avx512() {
            #[allow(unsafe_code)]
            // SAFETY: the CPU has AVX-512F (checked just above), the only
            // requirement of a `target_feature` function.
            unsafe {
                bounded_row_avx512(row, limits, scratch);
            }
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::avx2_fma() {
            #[allow(unsafe_code)]
            // SAFETY: the CPU has AVX2 (checked just above), the only
            // requirement of a `target_feature` function.
            unsafe {
                bounded_row_avx2(row, limits, scratch);
            }
            return;
        }
        bounded_row_of(row, limits, scratch);
    }

    /// The cost of half a squared Mahalanobis length `q`.
    #[inline]
    pub(super) fn robust(&self, q: f64) -> f64 {
        if self.tail > 0.0 {
            0.5 * self.tail * log1p(2.0 * q / self.tail)
        } else {
            q
        }
    }

    /// Each pair's [`limit`] under `loosest`, for its appearance in `log_g`.
    fn limits<'s>(&self, log_g: &'s [f64], loosest: f64) -> impl Iterator<Item = f64> + 's {
        let (tail, gate) = (self.tail, self.gate);
        log_g.iter().map(move |&g| limit(g, tail, gate, loosest))
    }

    /// Human object `i`'s ray under `rotation` and its `alpha`.
    fn human_ray(&self, i: usize, rotation: &nalgebra::Matrix3<f64>) -> ([f64; 3], f64) {
        let w = rotation * self.human[i].0;
        ([w.x, w.y, w.z], self.alpha[i])
    }
}

/// What one row of [`Rays::half_lengths`] is computed from: the moved
/// human object, its ray, and the robot objects by coordinate, every
/// slice cut to one length.
struct RowInputs<'s> {
    moved: [f64; 3],
    w: [f64; 3],
    alpha: f64,
    inv: f64,
    xyz: [&'s [f64]; 3],
    u: [&'s [f64]; 3],
    var: &'s [f64],
}

/// A row's buffers in [`Costs::cheapest_two`], reused from row to row.
#[derive(Default)]
pub(super) struct RowScratch {
    /// The row's costs, where there are no rays.
    costs: Vec<f64>,
    /// The row's half squared lengths, where there are.
    lengths: Vec<f64>,
    /// Bit `l` of mask `k`: whether pair `k * MASK_LANES + l` may be taken
    /// ([`Rays::bounded_row`]).
    masks: Vec<u8>,
    /// The row's limits, where the costs hold none for what is asked.
    limits: Vec<f64>,
}

/// The row's half squared lengths into `out`, a lane per robot object: no
/// value depends on another, so vectors of any width give the same bits
/// (IEEE operations, no fused multiply-add).
#[inline(always)]
fn half_lengths_of(row: &RowInputs<'_>, out: &mut [f64]) {
    // Every slice cut to one length: no bounds checks in the loop, which
    // would keep it from being vectorised.
    let m = out.len();
    let [mx, my, mz] = row.moved;
    let (xs, ys, zs) = (&row.xyz[0][..m], &row.xyz[1][..m], &row.xyz[2][..m]);
    let (ux, uy, uz) = (&row.u[0][..m], &row.u[1][..m], &row.u[2][..m]);
    let var = &row.var[..m];
    for k in 0..m {
        let r = [mx - xs[k], my - ys[k], mz - zs[k]];
        out[k] = half_mahalanobis2(r, row.w, row.alpha, [ux[k], uy[k], uz[k]], var[k], row.inv);
    }
}

/// [`half_lengths_of`] in 512-bit vectors, eight robot objects at once.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn half_lengths_avx512(row: &RowInputs<'_>, out: &mut [f64]) {
    half_lengths_of(row, out);
}

/// [`half_lengths_of`] in 256-bit vectors, four robot objects at once
/// (AVX2 alone: Rust never fuses a multiply and an add unasked, so the
/// bits are the baseline's).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn half_lengths_avx2(row: &RowInputs<'_>, out: &mut [f64]) {
    half_lengths_of(row, out);
}

/// Pairs per mask of [`Rays::bounded_row`].
const MASK_LANES: usize = 8;

/// The half squared length below which a pair of appearance `g` may cost
/// less than `loosest`. A pair's cost is the untailed `q - g` beyond the
/// gate, and below it the tail's `tail / 2 ln(1 + x) - g`, `x = 2q /
/// tail`, which is at least `q (6 + 3x) / (6 + 6x + x^2) - g` for `x >= 0`
/// (`ln(1 + x)` bounded by a Padé approximant of a Stieltjes function,
/// below it, and within 2% of it up to the gate). Both grow with `q`, so
/// the pairs whose bound is below `loosest` are those below one length:
/// the root of the bound's quadratic below the gate, else the gate or the
/// untailed cost's own limit beyond it. A hair above that, so that
/// rounding never keeps out a pair the bound lets in (the scan checks
/// each pair let in exactly).
fn limit(g: f64, tail: f64, gate: f64, loosest: f64) -> f64 {
    let a = loosest + g;
    if a.is_nan() || a == f64::INFINITY {
        return f64::INFINITY;
    }
    if a <= 0.0 {
        return 0.0;
    }
    let k = 2.0 / tail;
    // `q (6 + 3kq) < a (6 + 6kq + k^2 q^2)`: a quadratic in q, opening
    // upwards while the bound's ceiling, 3 / k, is above `a`.
    let root = if a * k >= 3.0 {
        f64::INFINITY
    } else {
        let linear = 6.0 - 6.0 * a * k;
        let square = k * (3.0 - a * k);
        12.0 * a / (linear + (linear * linear + 24.0 * a * square).sqrt())
    };
    let limit = if root < gate { root } else { gate.max(a) };
    limit * (1.0 + 1e-9)
}

/// Whether a pair of half squared length `q` and appearance `g` may cost
/// less than `loosest` by the bound [`limit`] solves: its definition,
/// which the tests hold `limit` to.
#[cfg(test)]
fn may_take(q: f64, g: f64, tail: f64, gate: f64, loosest: f64) -> bool {
    if q >= gate {
        return q - g < loosest;
    }
    let x = 2.0 * q / tail;
    q * (3.0 * x + 6.0) < (loosest + g) * (6.0 + x * (6.0 + x))
}

/// [`Rays::bounded_row`] itself, in whatever vectors the caller's target
/// features let the compiler use.
#[inline(always)]
fn bounded_row_of(row: &RowInputs<'_>, limits: &[f64], scratch: &mut RowScratch) {
    let m = limits.len();
    let RowScratch { lengths, masks, .. } = scratch;
    lengths.resize(m, 0.0);
    masks.resize(m.div_ceil(MASK_LANES), 0);
    half_lengths_of(row, lengths);
    for ((mask, q), limit) in masks
        .iter_mut()
        .zip(lengths.chunks(MASK_LANES))
        .zip(limits.chunks(MASK_LANES))
    {
        let mut bits = 0u8;
        for (l, (q, limit)) in q.iter().zip(limit).enumerate() {
            bits |= u8::from(q < limit) << l;
        }
        *mask = bits;
    }
}

/// [`bounded_row_of`] in 256-bit vectors, each mask from two of them:
/// the same IEEE operations in the same order as [`half_mahalanobis2`]
/// (no fused multiply-add), so the same bits; the last `m % 8` pairs by
/// the scalar code itself.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn bounded_row_avx2(row: &RowInputs<'_>, limits: &[f64], scratch: &mut RowScratch) {
    use std::arch::x86_64::{
        __m256d, _CMP_LT_OQ, _mm256_add_pd, _mm256_cmp_pd, _mm256_div_pd, _mm256_loadu_pd,
        _mm256_movemask_pd, _mm256_mul_pd, _mm256_set1_pd, _mm256_storeu_pd, _mm256_sub_pd,
    };
    let m = limits.len();
    let RowScratch { lengths, masks, .. } = scratch;
    lengths.resize(m, 0.0);
    masks.resize(m.div_ceil(MASK_LANES), 0);
    let (xs, ys, zs) = (&row.xyz[0][..m], &row.xyz[1][..m], &row.xyz[2][..m]);
    let (ux, uy, uz) = (&row.u[0][..m], &row.u[1][..m], &row.u[2][..m]);
    let var = &row.var[..m];
    let splat = |x: f64| _mm256_set1_pd(x);
    let [mx, my, mz] = row.moved.map(splat);
    let [w0, w1, w2] = row.w.map(splat);
    let (alpha, inv, one, half) = (splat(row.alpha), splat(row.inv), splat(1.0), splat(0.5));
    let load = |s: &[f64], k: usize| -> __m256d {
        let lanes = &s[k..k + 4];
        #[allow(unsafe_code)]
        // SAFETY: `lanes` is four f64 (a slice of that length); loadu takes
        // any alignment.
        unsafe {
            _mm256_loadu_pd(lanes.as_ptr())
        }
    };
    let add = |a: __m256d, b: __m256d| _mm256_add_pd(a, b);
    let sub = |a: __m256d, b: __m256d| _mm256_sub_pd(a, b);
    let mul = |a: __m256d, b: __m256d| _mm256_mul_pd(a, b);
    let dot = |a: [__m256d; 3], b: [__m256d; 3]| {
        add(add(mul(a[0], b[0]), mul(a[1], b[1])), mul(a[2], b[2]))
    };
    let whole = m / MASK_LANES;
    for (chunk, mask) in masks.iter_mut().enumerate().take(whole) {
        let mut bits = 0u8;
        for half_chunk in 0..2 {
            let k = chunk * MASK_LANES + 4 * half_chunk;
            let r = [
                sub(mx, load(xs, k)),
                sub(my, load(ys, k)),
                sub(mz, load(zs, k)),
            ];
            let w = [w0, w1, w2];
            let u = [load(ux, k), load(uy, k), load(uz, k)];
            let (rr, wr, ur, wu) = (dot(r, r), dot(w, r), dot(u, r), dot(w, u));
            let a = mul(sub(rr, mul(mul(alpha, wr), wr)), inv);
            let b = mul(sub(ur, mul(mul(alpha, wu), wr)), inv);
            let uu = mul(sub(one, mul(mul(alpha, wu), wu)), inv);
            let c = load(var, k);
            let q = mul(
                half,
                sub(a, _mm256_div_pd(mul(mul(c, b), b), add(one, mul(c, uu)))),
            );
            let out = &mut lengths[k..k + 4];
            #[allow(unsafe_code)]
            // SAFETY: `out` is four f64 (a slice of that length); storeu
            // takes any alignment.
            unsafe {
                _mm256_storeu_pd(out.as_mut_ptr(), q);
            }
            let may = _mm256_cmp_pd::<_CMP_LT_OQ>(q, load(limits, k));
            bits |= (_mm256_movemask_pd(may) as u8) << (4 * half_chunk);
        }
        *mask = bits;
    }
    if let Some(last) = masks.get_mut(whole) {
        let mut bits = 0u8;
        for (l, k) in (whole * MASK_LANES..m).enumerate() {
            let r = [
                row.moved[0] - xs[k],
                row.moved[1] - ys[k],
                row.moved[2] - zs[k],
            ];
            let q = half_mahalanobis2(r, row.w, row.alpha, [ux[k], uy[k], uz[k]], var[k], row.inv);
            lengths[k] = q;
            bits |= u8::from(q < limits[k]) << l;
        }
        *last = bits;
    }
}

/// [`bounded_row_avx2`] in 512-bit vectors: a mask is one vector's
/// compare, the same operations in the same order.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn bounded_row_avx512(row: &RowInputs<'_>, limits: &[f64], scratch: &mut RowScratch) {
    use std::arch::x86_64::{
        __m512d, _CMP_LT_OQ, _mm512_add_pd, _mm512_cmp_pd_mask, _mm512_div_pd, _mm512_loadu_pd,
        _mm512_mul_pd, _mm512_set1_pd, _mm512_storeu_pd, _mm512_sub_pd,
    };
    let m = limits.len();
    let RowScratch { lengths, masks, .. } = scratch;
    lengths.resize(m, 0.0);
    masks.resize(m.div_ceil(MASK_LANES), 0);
    let (xs, ys, zs) = (&row.xyz[0][..m], &row.xyz[1][..m], &row.xyz[2][..m]);
    let (ux, uy, uz) = (&row.u[0][..m], &row.u[1][..m], &row.u[2][..m]);
    let var = &row.var[..m];
    let splat = |x: f64| _mm512_set1_pd(x);
    let [mx, my, mz] = row.moved.map(splat);
    let w = row.w.map(splat);
    let (alpha, inv, one, half) = (splat(row.alpha), splat(row.inv), splat(1.0), splat(0.5));
    let load = |s: &[f64], k: usize| -> __m512d {
        let lanes = &s[k..k + MASK_LANES];
        #[allow(unsafe_code)]
        // SAFETY: `lanes` is eight f64 (a slice of that length); loadu
        // takes any alignment.
        unsafe {
            _mm512_loadu_pd(lanes.as_ptr())
        }
    };
    let add = |a: __m512d, b: __m512d| _mm512_add_pd(a, b);
    let sub = |a: __m512d, b: __m512d| _mm512_sub_pd(a, b);
    let mul = |a: __m512d, b: __m512d| _mm512_mul_pd(a, b);
    let dot = |a: [__m512d; 3], b: [__m512d; 3]| {
        add(add(mul(a[0], b[0]), mul(a[1], b[1])), mul(a[2], b[2]))
    };
    let whole = m / MASK_LANES;
    for (chunk, mask) in masks.iter_mut().enumerate().take(whole) {
        let k = chunk * MASK_LANES;
        let r = [
            sub(mx, load(xs, k)),
            sub(my, load(ys, k)),
            sub(mz, load(zs, k)),
        ];
        let u = [load(ux, k), load(uy, k), load(uz, k)];
        let (rr, wr, ur, wu) = (dot(r, r), dot(w, r), dot(u, r), dot(w, u));
        let a = mul(sub(rr, mul(mul(alpha, wr), wr)), inv);
        let b = mul(sub(ur, mul(mul(alpha, wu), wr)), inv);
        let uu = mul(sub(one, mul(mul(alpha, wu), wu)), inv);
        let c = load(var, k);
        let q = mul(
            half,
            sub(a, _mm512_div_pd(mul(mul(c, b), b), add(one, mul(c, uu)))),
        );
        let out = &mut lengths[k..k + MASK_LANES];
        #[allow(unsafe_code)]
        // SAFETY: `out` is eight f64 (a slice of that length); storeu
        // takes any alignment.
        unsafe {
            _mm512_storeu_pd(out.as_mut_ptr(), q);
        }
        *mask = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(q, load(limits, k));
    }
    if let Some(last) = masks.get_mut(whole) {
        let mut bits = 0u8;
        for (l, k) in (whole * MASK_LANES..m).enumerate() {
            let r = [
                row.moved[0] - xs[k],
                row.moved[1] - ys[k],
                row.moved[2] - zs[k],
            ];
            let q = half_mahalanobis2(r, row.w, row.alpha, [ux[k], uy[k], uz[k]], var[k], row.inv);
            lengths[k] = q;
            bits |= u8::from(q < limits[k]) << l;
        }
        *last = bits;
    }
}

/// Half of `r^T C^-1 r` for `C = I / inv + h w w^T + c u u^T` (`alpha`
/// = h / (1 / inv + h)), by Sherman-Morrison twice.
#[inline(always)]
fn half_mahalanobis2(r: [f64; 3], w: [f64; 3], alpha: f64, u: [f64; 3], c: f64, inv: f64) -> f64 {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (rr, wr, ur, wu) = (dot(r, r), dot(w, r), dot(u, r), dot(w, u));
    let a = (rr - alpha * wr * wr) * inv;
    let b = (ur - alpha * wu * wr) * inv;
    let uu = (1.0 - alpha * wu * wu) * inv;
    0.5 * (a - c * b * b / (1.0 + c * uu))
}

impl<'a> Costs<'a> {
    /// The costs of `problem` with residual scales from the robot view's
    /// object `spacing`: the ray model for views in camera frames (with the
    /// sensors' stated errors, else `depth_error`), the stated errors
    /// isotropically for other views that state any, else one isotropic
    /// sigma.
    pub(super) fn new(
        problem: &'a Problem,
        log_g: &'a [f64],
        spacing: f64,
        rp: &RigidParams,
    ) -> Self {
        let axis = |k: usize| problem.robot_positions.iter().map(|p| p[k]).collect();
        let sigma = rp.sigma_factor * spacing;
        let sigma2 = sigma * sigma;
        let variances = [problem.human_variances(), problem.robot_variances()];
        let rays = Rays::of(problem, &variances, rp, rp.lateral_factor * spacing);
        // Stated errors of views that are not in camera frames: isotropic.
        let stated =
            (rays.is_none() && rp.stated_errors && has_stated_errors(problem)).then(|| {
                let (n, m) = (problem.n, problem.m);
                let mut inv = Vec::with_capacity(n * m);
                for i in 0..n {
                    for j in 0..m {
                        let s2 = sigma2 + variance(&variances[0], i) + variance(&variances[1], j);
                        inv.push(1.0 / (2.0 * s2));
                    }
                }
                inv
            });
        // The search's tolerances follow the typical pair's scale.
        let typical = if stated.is_some() {
            (sigma2 + median(&variances[0]) + median(&variances[1])).sqrt()
        } else if let Some(rays) = &rays {
            rays.typical()
        } else {
            sigma
        };
        let limits_for = rp.unmatched_cost + BOUND_MARGIN;
        Self {
            problem,
            log_g,
            inv_two_sigma2: 1.0 / (2.0 * sigma2),
            stated,
            robot_xyz: [axis(0), axis(1), axis(2)],
            rays,
            typical,
            limits: std::cell::OnceCell::new(),
            limits_for,
        }
    }

    /// These costs with the ray model's scales set to `noise` (no change
    /// for views without rays).
    pub(super) fn with_noise(&self, noise: Noise) -> Self {
        let mut rays = self.rays.clone();
        let mut typical = self.typical;
        if let Some(r) = &mut rays {
            r.set(noise);
            typical = r.typical();
        }
        Self {
            problem: self.problem,
            log_g: self.log_g,
            inv_two_sigma2: self.inv_two_sigma2,
            stated: self.stated.clone(),
            robot_xyz: self.robot_xyz.clone(),
            rays,
            typical,
            // A pair's limit depends on its appearance, the tail and the
            // gate (both from the constants), not on the noise scales: the
            // lengths it is compared with are in units of the noise.
            limits: self.limits.clone(),
            limits_for: self.limits_for,
        }
    }

    /// Costs of human object `i`, moved to `moved`, against every robot
    /// object, into `out` (length m).
    pub(super) fn row(&self, i: usize, motion: &RigidMotion, out: &mut [f64]) {
        let m = self.problem.m;
        let moved = &motion.apply(&self.problem.human_positions[i]);
        let log_g = &self.log_g[i * m..(i + 1) * m];
        let [xs, ys, zs] = &self.robot_xyz;
        if let Some(rays) = &self.rays {
            rays.row(i, motion, moved, &self.robot_xyz, out);
            for (o, g) in out.iter_mut().zip(log_g) {
                *o -= g;
            }
            return;
        }
        if let Some(inv) = &self.stated {
            let inv = &inv[i * m..(i + 1) * m];
            for (k, o) in out.iter_mut().enumerate() {
                let (dx, dy, dz) = (moved.x - xs[k], moved.y - ys[k], moved.z - zs[k]);
                *o = (dx * dx + dy * dy + dz * dz) * inv[k] - log_g[k];
            }
            return;
        }
        let inv = self.inv_two_sigma2;
        for ((((o, &g), &x), &y), &z) in out.iter_mut().zip(log_g).zip(xs).zip(ys).zip(zs) {
            let (dx, dy, dz) = (moved.x - x, moved.y - y, moved.z - z);
            *o = (dx * dx + dy * dy + dz * dz) * inv - g;
        }
    }

    /// The two cheapest pairs of human object `i` under `motion` that cost
    /// less than `below`, cheapest first (the lower column first among
    /// equal costs), `(INFINITY, usize::MAX)` where there are fewer: what
    /// scanning [`Costs::row`] finds, computed with fewer logarithms. The
    /// search asks this of thousands of rows.
    pub(super) fn cheapest_two(
        &self,
        i: usize,
        motion: &RigidMotion,
        below: f64,
        scratch: &mut RowScratch,
    ) -> [(f64, usize); 2] {
        let m = self.problem.m;
        let mut best = [(f64::INFINITY, usize::MAX); 2];
        let offer = |c: f64, j: usize, best: &mut [(f64, usize); 2]| {
            if c < best[0].0 {
                best[1] = best[0];
                best[0] = (c, j);
            } else if c < best[1].0 {
                best[1] = (c, j);
            }
        };
        let Some(rays) = self.rays.as_ref().filter(|r| r.tail > 0.0) else {
            scratch.costs.resize(m, 0.0);
            self.row(i, motion, &mut scratch.costs);
            for (j, &c) in scratch.costs.iter().enumerate() {
                if c < below {
                    offer(c, j, &mut best);
                }
            }
            return best;
        };
        let moved = motion.apply(&self.problem.human_positions[i]);
        let log_g = &self.log_g[i * m..(i + 1) * m];
        let row = rays.row_inputs(i, motion, &moved, &self.robot_xyz, m);
        // Every pair that may be taken has its bound below this: the
        // search's rows all ask for pairs below "no partner", whose
        // limits are computed once.
        let loosest = below + BOUND_MARGIN;
        let mut own = std::mem::take(&mut scratch.limits);
        let limits = if loosest == self.limits_for {
            let all = self.limits.get_or_init(|| {
                rays.limits(&self.log_g[..self.problem.n * m], loosest)
                    .collect()
            });
            &all[i * m..(i + 1) * m]
        } else {
            own.clear();
            own.extend(rays.limits(log_g, loosest));
            &own[..]
        };
        rays.bounded_row(&row, limits, scratch);
        scratch.limits = own;
        let tail = rays.tail;
        for (chunk, &mask) in scratch.masks.iter().enumerate() {
            let mut bits = mask;
            while bits != 0 {
                let j = chunk * MASK_LANES + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let (q, g) = (scratch.lengths[j], log_g[j]);
                if q >= rays.gate {
                    // Untailed beyond the gate, as `row` leaves it.
                    if q - g < below {
                        offer(q - g, j, &mut best);
                    }
                    continue;
                }
                // The bound again, against what the pair must beat now
                // that pairs were offered; multiplied out, without a
                // division.
                let x = 2.0 * q / tail;
                let beat = below.min(best[1].0) + g + BOUND_MARGIN;
                if q * (3.0 * x + 6.0) >= beat * (6.0 + x * (6.0 + x)) {
                    continue;
                }
                let c = rays.robust(q) - g;
                if c < below {
                    offer(c, j, &mut best);
                }
            }
        }
        best
    }

    /// Row-major `n x m` costs under `motion`: the tail applied to every
    /// pair, however far (the shares weigh pairs beyond the gate too).
    pub(super) fn matrix(&self, motion: Option<&RigidMotion>) -> Vec<f64> {
        let (n, m) = (self.problem.n, self.problem.m);
        let Some(t) = motion.filter(|_| m > 0) else {
            return self.log_g.iter().take(n * m).map(|g| -g).collect();
        };
        let mut out = vec![0.0; n * m];
        for (i, row) in out.chunks_exact_mut(m).enumerate() {
            let Some(rays) = &self.rays else {
                self.row(i, t, row);
                continue;
            };
            let moved = t.apply(&self.problem.human_positions[i]);
            rays.half_lengths(i, t, &moved, &self.robot_xyz, row);
            for (o, g) in row.iter_mut().zip(&self.log_g[i * m..(i + 1) * m]) {
                *o = rays.robust(*o) - g;
            }
        }
        out
    }
}

/// Whether either view states a position error for some object.
fn has_stated_errors(problem: &Problem) -> bool {
    problem
        .human_sigmas
        .iter()
        .chain(&problem.robot_sigmas)
        .flatten()
        .any(|&s| s > 0.0)
}

/// Entry `k` of a per-object list that may be empty (nothing stated).
fn variance(list: &[f64], k: usize) -> f64 {
    list.get(k).copied().unwrap_or(0.0)
}

fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied().unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use nalgebra::{Matrix3, Vector3};

    use nalgebra::Point3;

    use super::{Costs, Rays, RowScratch};
    use crate::RigidMotion;
    use crate::methods::rigid::RigidParams;
    use crate::methods::rigid::search::SplitMix;

    /// The Sherman-Morrison form against the covariance inverted outright.
    #[test]
    fn ray_distance_is_the_mahalanobis_distance_of_the_ray_covariance() {
        let mut rng = SplitMix(7);
        let mut unit = || (rng.next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        for _ in 0..200 {
            let mut vector = || Vector3::new(unit(), unit(), unit());
            let (r, w, u) = (vector(), vector().normalize(), vector().normalize());
            let (lateral, h, c) = (0.01 + unit().abs(), 4.0 * unit().abs(), 4.0 * unit().abs());
            let mut rays = Rays {
                human: vec![(w, h)],
                robot_u: [vec![u.x], vec![u.y], vec![u.z]],
                robot_var: vec![c],
                human_base: vec![h],
                robot_base: vec![c],
                lateral,
                inv_lateral: 0.0,
                alpha: Vec::new(),
                noise: super::Noise {
                    lateral,
                    robot: 1.0,
                    human: 1.0,
                },
                assumed: true,
                tail: 0.0,
                gate: f64::INFINITY,
            };
            rays.set(rays.noise);
            let covariance =
                Matrix3::identity() * lateral + w * w.transpose() * h + u * u.transpose() * c;
            let expected = 0.5 * (r.transpose() * covariance.try_inverse().unwrap() * r)[0];
            let (w_moved, alpha) = rays.human_ray(0, &Matrix3::identity());
            let got = rays.half_distance2([r.x, r.y, r.z], w_moved, alpha, 0);
            assert!(
                (got - expected).abs() <= 1e-9 * expected.max(1.0),
                "{got} against {expected}"
            );
        }
    }

    /// An error along the ray costs what its variance says, one across it
    /// only the lateral scale's: the model that tells look-alikes apart
    /// where depth error is large.
    #[test]
    fn error_along_the_ray_costs_less_than_across_it() {
        let mut rays = Rays {
            human: vec![(Vector3::z(), 0.0)],
            robot_u: [vec![0.0], vec![0.0], vec![1.0]],
            robot_var: vec![3.0],
            human_base: vec![0.0],
            robot_base: vec![3.0],
            lateral: 1.0,
            inv_lateral: 0.0,
            alpha: Vec::new(),
            noise: super::Noise {
                lateral: 1.0,
                robot: 1.0,
                human: 1.0,
            },
            assumed: true,
            tail: 0.0,
            gate: f64::INFINITY,
        };
        rays.set(rays.noise);
        let (w, alpha) = rays.human_ray(0, &Matrix3::identity());
        let along = rays.half_distance2([0.0, 0.0, 2.0], w, alpha, 0);
        let across = rays.half_distance2([2.0, 0.0, 0.0], w, alpha, 0);
        assert!((along - 0.5).abs() < 1e-12, "{along}");
        assert!((across - 2.0).abs() < 1e-12, "{across}");
    }

    /// A scene of `n` human and `m` robot objects near each other, in
    /// front of both cameras (`in_front`) or not, with random appearance.
    fn scene(rng: &mut SplitMix, n: usize, m: usize, in_front: bool) -> crate::Problem {
        let mut unit = || (rng.next() >> 11) as f64 / (1u64 << 53) as f64;
        let points = |k: usize, unit: &mut dyn FnMut() -> f64| -> Vec<Point3<f64>> {
            (0..k)
                .map(|_| {
                    let z = if in_front { 0.8 + 0.3 * unit() } else { 0.0 };
                    Point3::new(0.3 * unit(), 0.2 * unit(), z)
                })
                .collect()
        };
        let human_positions = points(n, &mut unit);
        let robot_positions = points(m, &mut unit);
        let appearance = (0..n * m).map(|_| unit()).collect();
        crate::Problem {
            n,
            m,
            appearance,
            spatial: crate::SpatialTerm::Pairs(crate::PairAffinity::new(
                n,
                m,
                Vec::new(),
                &vec![0.0; n * n],
                &vec![0.0; m * m],
                0.01,
            )),
            human_positions,
            robot_positions,
            human_sigmas: Vec::new(),
            robot_sigmas: Vec::new(),
            human_up: None,
            robot_up: None,
        }
    }

    /// `cheapest_two` is what scanning the whole row finds, to the bit,
    /// with the tail, without it, and without rays; `matrix` is the tailed
    /// cost of every pair.
    #[test]
    fn the_cheapest_two_and_the_matrix_are_the_rows_costs() {
        let mut rng = SplitMix(11);
        let mut bounded = 0;
        for case in 0..60 {
            let rp = RigidParams {
                tail: if case % 3 == 2 { 0.0 } else { 6.0 },
                ..RigidParams::default()
            };
            let (n, m) = (2 + rng.below(12), 1 + rng.below(12));
            let problem = scene(&mut rng, n, m, case % 5 != 4);
            let log_g = super::super::appearance_log_likelihood(&problem, 0.2, 0.1);
            let costs = Costs::new(&problem, &log_g, 0.05, &rp);
            let angle = 0.05 * (rng.below(100) as f64 / 100.0);
            let motion = RigidMotion {
                rotation: *nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), angle).matrix(),
                translation: Vector3::new(0.01 * rng.below(3) as f64, 0.0, 0.0),
            };
            let matrix = costs.matrix(Some(&motion));
            let mut row = vec![0.0; m];
            let mut buf = RowScratch::default();
            for i in 0..n {
                costs.row(i, &motion, &mut row);
                for below in [rp.unmatched_cost, 1.0, f64::INFINITY] {
                    let mut expected = [(f64::INFINITY, usize::MAX); 2];
                    for (j, &c) in row.iter().enumerate() {
                        if c < below && c < expected[0].0 {
                            expected = [(c, j), expected[0]];
                        } else if c < below && c < expected[1].0 {
                            expected[1] = (c, j);
                        }
                    }
                    let got = costs.cheapest_two(i, &motion, below, &mut buf);
                    assert_eq!(got, expected, "case {case} row {i} below {below}");
                    bounded += usize::from(got[1].1 != usize::MAX);
                }
                let Some(rays) = &costs.rays else {
                    assert_eq!(&matrix[i * m..(i + 1) * m], &row[..], "case {case}");
                    continue;
                };
                let moved = motion.apply(&problem.human_positions[i]);
                let (w, alpha) = rays.human_ray(i, &motion.rotation);
                for j in 0..m {
                    let r = moved - problem.robot_positions[j];
                    let q = rays.half_distance2([r.x, r.y, r.z], w, alpha, j);
                    assert_eq!(matrix[i * m + j], rays.robust(q) - log_g[i * m + j]);
                }
            }
        }
        assert!(
            bounded > 100,
            "too few rows with two pairs below: {bounded}"
        );
    }

    /// The masks' bound never drops a pair that costs less than what it
    /// must beat (on either side of the gate, with any appearance), and
    /// is close: of the pairs it keeps below the gate, few cost more.
    #[test]
    fn the_bound_keeps_every_pair_below_what_it_must_beat() {
        let rp = RigidParams::default();
        let (tail, unmatched) = (rp.tail, rp.unmatched_cost);
        let gate = 0.5 * tail * (2.0 * unmatched / tail).exp_m1();
        let mut rng = SplitMix(11);
        let (mut kept, mut dearer) = (0, 0);
        for _ in 0..200_000 {
            let uniform = |rng: &mut SplitMix| rng.below(1 << 30) as f64 / (1 << 30) as f64;
            let q = 2.0 * gate * uniform(&mut rng);
            let g = 4.0 * uniform(&mut rng) - 3.0;
            let loosest = 7.0 * uniform(&mut rng) - 1.0;
            let cost = if q >= gate {
                q - g
            } else {
                0.5 * tail * super::log1p(2.0 * q / tail) - g
            };
            let may = super::may_take(q, g, tail, gate, loosest);
            assert!(may || cost >= loosest, "q {q} g {g} loosest {loosest}");
            // The masks' limit lets in every pair the bound lets in, and
            // hardly more.
            let limit = super::limit(g, tail, gate, loosest);
            assert!(!may || q < limit, "q {q} g {g} loosest {loosest}");
            assert!(
                may || q >= limit * (1.0 - 1e-8),
                "q {q} g {g} loosest {loosest}: let in for nothing"
            );
            if may && q < gate {
                kept += 1;
                dearer += usize::from(cost >= loosest);
            }
        }
        assert!(kept > 10_000, "{kept}");
        assert!(
            dearer * 50 < kept,
            "{dearer} of {kept} kept pairs cost more"
        );
    }

    /// The vector paths give the rows' lengths and masks to the bit, at
    /// every length (whole vectors and remainders): they decide which pairs
    /// the search looks at, so a difference would change answers by CPU.
    #[test]
    fn the_vector_rows_are_the_baseline_rows() {
        let mut rng = SplitMix(5);
        let rp = RigidParams::default();
        let mut marked = 0;
        for case in 0..40 {
            let (n, m) = (3, 1 + rng.below(40));
            let problem = scene(&mut rng, n, m, true);
            let log_g = super::super::appearance_log_likelihood(&problem, 0.2, 0.1);
            let costs = Costs::new(&problem, &log_g, 0.05, &rp);
            let rays = costs
                .rays
                .as_ref()
                .expect("a scene in front of its cameras");
            let motion = RigidMotion {
                rotation: *nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), 0.03).matrix(),
                translation: Vector3::new(0.01, 0.0, 0.0),
            };
            for i in 0..n {
                let moved = motion.apply(&problem.human_positions[i]);
                let row = rays.row_inputs(i, &motion, &moved, &costs.robot_xyz, m);
                let log_g = &log_g[i * m..(i + 1) * m];
                let limits: Vec<f64> = rays.limits(log_g, rp.unmatched_cost).collect();
                let mut scalar = RowScratch::default();
                super::bounded_row_of(&row, &limits, &mut scalar);
                let mut dispatched = RowScratch::default();
                rays.bounded_row(&row, &limits, &mut dispatched);
                assert_eq!(scalar.masks, dispatched.masks, "case {case} row {i}");
                for (path, vector) in vector_paths(&row, &limits) {
                    assert_eq!(
                        scalar.lengths, vector.lengths,
                        "{path}: case {case} row {i}"
                    );
                    assert_eq!(scalar.masks, vector.masks, "{path}: case {case} row {i}");
                    let mut lengths = vec![0.0; m];
                    match path {
                        "avx2" => unsafe_half_lengths_avx2(&row, &mut lengths),
                        _ => unsafe_half_lengths_avx512(&row, &mut lengths),
                    }
                    assert_eq!(scalar.lengths, lengths, "{path}: case {case} row {i}");
                }
                marked += scalar.masks.iter().map(|b| b.count_ones()).sum::<u32>();
                for (j, &q) in scalar.lengths.iter().enumerate() {
                    let r = moved - problem.robot_positions[j];
                    let (w, alpha) = rays.human_ray(i, &motion.rotation);
                    assert_eq!(q, rays.half_distance2([r.x, r.y, r.z], w, alpha, j));
                }
            }
        }
        assert!(marked > 20, "too few pairs marked: {marked}");
    }

    /// Each vector path this CPU has, run on `row`; a path it lacks is
    /// reported as skipped (the test then checks fewer paths, never the
    /// baseline against itself).
    fn vector_paths(row: &super::RowInputs<'_>, limits: &[f64]) -> Vec<(&'static str, RowScratch)> {
        let mut out = Vec::new();
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                let mut s = RowScratch::default();
                #[allow(unsafe_code)]
                // SAFETY: the CPU has AVX2 (checked just above).
                unsafe {
                    super::bounded_row_avx2(row, limits, &mut s);
                }
                out.push(("avx2", s));
            } else {
                eprintln!("skipped: this CPU has no AVX2");
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                let mut s = RowScratch::default();
                #[allow(unsafe_code)]
                // SAFETY: the CPU has AVX-512F (checked just above).
                unsafe {
                    super::bounded_row_avx512(row, limits, &mut s);
                }
                out.push(("avx512", s));
            } else {
                eprintln!("skipped: this CPU has no AVX-512F");
            }
        }
        out
    }

    /// The AVX2 path of the row's lengths alone (the CPU has AVX2: only
    /// called for a path [`vector_paths`] ran).
    #[cfg(target_arch = "x86_64")]
    fn unsafe_half_lengths_avx2(row: &super::RowInputs<'_>, out: &mut [f64]) {
        #[allow(unsafe_code)]
        // SAFETY: called only where `vector_paths` found AVX2.
        unsafe {
            super::half_lengths_avx2(row, out);
        }
    }

    /// The AVX-512 path of the row's lengths alone.
    #[cfg(target_arch = "x86_64")]
    fn unsafe_half_lengths_avx512(row: &super::RowInputs<'_>, out: &mut [f64]) {
        #[allow(unsafe_code)]
        // SAFETY: called only where `vector_paths` found AVX-512F.
        unsafe {
            super::half_lengths_avx512(row, out);
        }
    }
}
