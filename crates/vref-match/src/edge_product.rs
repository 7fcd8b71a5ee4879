//! The inner loops of the exact tier's S x product for a fully connected
//! robot graph, and of its kernel table, written for the x86-64 baseline
//! (SSE2) and, chosen at run time when the CPU has them, for AVX2 with FMA
//! and for AVX-512, so the binary still runs on any x86-64.
//!
//! One human edge `{i, j}` adds `K x_j` to row i of out and `K x_i` to row
//! j, K the symmetric `m x m` matrix (zero diagonal) of its kernel values
//! against the robot edges `{a, b}`. Its table row holds K's upper triangle
//! in blocks of [`ROWS`] robot rows: rows `a0 .. a0 + ROWS` (`a0 = 0, 4,
//! ..`) each hold the columns `b = a0 .. padded(m)`, zero where `b <= a` or
//! `b >= m`, stored a chunk of [`LANES`] columns at a time: the chunk's
//! values of row `a0`, then of row `a0 + 1`, and so on (so one 512-bit
//! load widens two rows' chunk). A few zeros (16% more values at 32
//! objects, 8% at 64) buy loops of whole vectors only: no remainders, no
//! small triangle inside a block, no per-row sums.

use crate::fast_exp::exp_neg_single_with;

/// Kernel values are stored as f32: half the memory traffic of f64 (the
/// table is read once per product and is megabytes), and a relative error
/// of 6e-8, well inside the 1e-6 the product is tested to. Sums and x
/// stay f64.
pub(crate) type Kernel = f32;

/// Robot rows per block of the layout, handled together: their updates of
/// `out_i[b]` and `out_j[b]` share one load and store of each, and
/// `x_i[b]`, `x_j[b]` are loaded once for all of them.
const ROWS: usize = 4;

/// f64 lanes of one 256-bit vector.
const LANES: usize = 4;

/// Values of one chunk of a block: [`LANES`] columns of its [`ROWS`] rows.
const CHUNK: usize = ROWS * LANES;

/// `m` rounded up to whole vectors: the row length of x and out the
/// product needs.
pub(crate) fn padded(m: usize) -> usize {
    m.div_ceil(LANES) * LANES
}

/// The slots of one table row for a complete robot graph of `m` objects,
/// in order: `Some((a, b))` for the robot edge `{a, b}`, `a < b`, `None`
/// for padding.
pub(crate) fn block_slots(m: usize) -> Vec<Option<(usize, usize)>> {
    let p = padded(m);
    let mut slots = Vec::new();
    for a0 in (0..p).step_by(ROWS) {
        for c0 in (a0..p).step_by(LANES) {
            for a in a0..a0 + ROWS {
                slots.extend((c0..c0 + LANES).map(|b| (a < b && b < m).then_some((a, b))));
            }
        }
    }
    slots
}

/// Position of robot edge `{a, b}`, `a < b < m`, in [`block_slots`].
pub(crate) fn block_slot(a: usize, b: usize, m: usize) -> usize {
    let p = padded(m);
    let block = a / ROWS;
    let a0 = block * ROWS;
    // Block `q` holds ROWS rows of `p - ROWS q` values.
    let before = ROWS * (block * p - ROWS * block * block.saturating_sub(1) / 2);
    let (chunk, lane) = ((b - a0) / LANES, (b - a0) % LANES);
    before + chunk * CHUNK + (a - a0) * LANES + lane
}

/// For one human edge `{i, j}` with table row `k` against a complete robot
/// graph of `m` objects: adds `K x_j` to `oi` and `K x_i` to `oj`. The four
/// slices hold [`padded`]`(m)` values; x must be zero past `m`.
pub(crate) fn edge_product(
    m: usize,
    k: &[Kernel],
    xi: &[f64],
    xj: &[f64],
    oi: &mut [f64],
    oj: &mut [f64],
) {
    #[cfg(target_arch = "x86_64")]
    if simd::edge_product_512(m, k, xi, xj, oi, oj) || simd::edge_product(m, k, xi, xj, oi, oj) {
        return;
    }
    edge_product_with(m, k, xi, xj, oi, oj);
}

/// Appends `exp(-(length - f)^2 / beta)` for every `f` of `robot_lengths`
/// (an infinite `f`, padding, gives 0).
pub(crate) fn extend_kernel_row(
    row: &mut Vec<Kernel>,
    length: f64,
    robot_lengths: &[f64],
    beta: f64,
) {
    #[cfg(target_arch = "x86_64")]
    if simd::extend_kernel_row_512(row, length, robot_lengths, beta)
        || simd::extend_kernel_row(row, length, robot_lengths, beta)
    {
        return;
    }
    extend_kernel_row_with::<false>(row, length, robot_lengths, beta);
}

/// The kernel with `1 / beta` given: a multiplication instead of a
/// division per value (the division cost as much as the rest of `exp`);
/// the argument moves by an ulp at most, far below f32's rounding.
#[inline(always)]
fn kernel_scaled<const FMA: bool>(length: f64, robot_length: f64, inverse_beta: f64) -> Kernel {
    let diff = length - robot_length;
    exp_neg_single_with::<FMA>(diff * diff * inverse_beta) as Kernel
}

#[inline(always)]
fn extend_kernel_row_with<const FMA: bool>(
    row: &mut Vec<Kernel>,
    length: f64,
    robot_lengths: &[f64],
    beta: f64,
) {
    // A plain loop over a slice rather than `extend` with an iterator: it is
    // inlined into the AVX2 copy and vectorised there.
    let inverse_beta = 1.0 / beta;
    let from = row.len();
    row.resize(from + robot_lengths.len(), 0.0);
    for (value, &f) in row[from..].iter_mut().zip(robot_lengths) {
        *value = kernel_scaled::<FMA>(length, f, inverse_beta);
    }
}

/// The baseline loops; the compiler vectorises the lanes with SSE2.
fn edge_product_with(
    m: usize,
    k: &[Kernel],
    xi: &[f64],
    xj: &[f64],
    oi: &mut [f64],
    oj: &mut [f64],
) {
    let p = padded(m);
    let (xi, xj, oi, oj) = (&xi[..p], &xj[..p], &mut oi[..p], &mut oj[..p]);
    let mut start = 0;
    for a0 in (0..p).step_by(ROWS) {
        let len = p - a0;
        let block = &k[start..start + ROWS * len];
        start += ROWS * len;
        let xia: [f64; ROWS] = std::array::from_fn(|r| xi[a0 + r]);
        let xja: [f64; ROWS] = std::array::from_fn(|r| xj[a0 + r]);
        let (mut si, mut sj) = ([[0.0; LANES]; ROWS], [[0.0; LANES]; ROWS]);
        for base in (0..len).step_by(LANES) {
            let b = a0 + base;
            let (xic, xjc) = (&xi[b..b + LANES], &xj[b..b + LANES]);
            let mut oic: [f64; LANES] = std::array::from_fn(|l| oi[b + l]);
            let mut ojc: [f64; LANES] = std::array::from_fn(|l| oj[b + l]);
            for r in 0..ROWS {
                let at = base * ROWS + r * LANES;
                let kc = &block[at..at + LANES];
                for l in 0..LANES {
                    let kv = f64::from(kc[l]);
                    si[r][l] += kv * xjc[l];
                    sj[r][l] += kv * xic[l];
                    oic[l] += kv * xja[r];
                    ojc[l] += kv * xia[r];
                }
            }
            oi[b..b + LANES].copy_from_slice(&oic);
            oj[b..b + LANES].copy_from_slice(&ojc);
        }
        for r in 0..ROWS {
            oi[a0 + r] += si[r].iter().sum::<f64>();
            oj[a0 + r] += sj[r].iter().sum::<f64>();
        }
    }
}

/// The product with AVX2 and FMA intrinsics, used when the CPU has both:
/// the compiler's own vectorisation of the blocked loop in a
/// `target_feature` function spilled its accumulators and fell back to
/// scalar FMAs.
#[cfg(target_arch = "x86_64")]
mod simd {
    use std::arch::x86_64::{
        __m256d, __m512d, _mm256_add_pd, _mm256_cvtps_pd, _mm256_fmadd_pd, _mm256_hadd_pd,
        _mm256_permute2f128_pd, _mm256_set1_pd, _mm256_setzero_pd, _mm512_broadcast_f64x4,
        _mm512_castpd512_pd256, _mm512_cvtps_pd, _mm512_extractf64x4_pd, _mm512_fmadd_pd,
        _mm512_insertf64x4, _mm512_mul_pd, _mm512_set1_pd, _mm512_setzero_pd,
    };

    use super::{CHUNK, Kernel, LANES, ROWS, padded};

    // `sums` turns one vector per row into one vector of rows.
    const _: () = assert!(ROWS == LANES && LANES == 4);

    /// False, and nothing done, when the CPU lacks AVX-512F.
    pub(super) fn edge_product_512(
        m: usize,
        k: &[Kernel],
        xi: &[f64],
        xj: &[f64],
        oi: &mut [f64],
        oj: &mut [f64],
    ) -> bool {
        if !crate::cpu::avx512() {
            return false;
        }
        #[allow(unsafe_code)]
        // SAFETY: the CPU has AVX-512F, AVX2 and FMA (checked just above),
        // the only requirement of a `target_feature` function.
        unsafe {
            edge_product_avx512(m, k, xi, xj, oi, oj)
        }
        true
    }

    /// False, and nothing done, when the CPU lacks AVX2 and FMA.
    pub(super) fn edge_product(
        m: usize,
        k: &[Kernel],
        xi: &[f64],
        xj: &[f64],
        oi: &mut [f64],
        oj: &mut [f64],
    ) -> bool {
        if !crate::cpu::avx2_fma() {
            return false;
        }
        #[allow(unsafe_code)]
        // SAFETY: the CPU has AVX2 and FMA (checked just above), the only
        // requirement of a `target_feature` function.
        unsafe {
            edge_product_avx2(m, k, xi, xj, oi, oj)
        }
        true
    }

    /// False, and nothing done, when the CPU lacks AVX2 and FMA.
    pub(super) fn extend_kernel_row(
        row: &mut Vec<Kernel>,
        length: f64,
        robot_lengths: &[f64],
        beta: f64,
    ) -> bool {
        if !crate::cpu::avx2_fma() {
            return false;
        }
        #[allow(unsafe_code)]
        // SAFETY: as in `edge_product`.
        unsafe {
            extend_kernel_row_avx2(row, length, robot_lengths, beta)
        }
        true
    }

    /// False, and nothing done, when the CPU lacks AVX-512F.
    pub(super) fn extend_kernel_row_512(
        row: &mut Vec<Kernel>,
        length: f64,
        robot_lengths: &[f64],
        beta: f64,
    ) -> bool {
        if !crate::cpu::avx512() {
            return false;
        }
        #[allow(unsafe_code)]
        // SAFETY: as in `edge_product_512`.
        unsafe {
            extend_kernel_row_avx512(row, length, robot_lengths, beta)
        }
        true
    }

    #[target_feature(enable = "avx512f,avx2,fma")]
    fn extend_kernel_row_avx512(
        row: &mut Vec<Kernel>,
        length: f64,
        robot_lengths: &[f64],
        beta: f64,
    ) {
        super::extend_kernel_row_with::<true>(row, length, robot_lengths, beta);
    }

    #[target_feature(enable = "avx2,fma")]
    fn extend_kernel_row_avx2(
        row: &mut Vec<Kernel>,
        length: f64,
        robot_lengths: &[f64],
        beta: f64,
    ) {
        super::extend_kernel_row_with::<true>(row, length, robot_lengths, beta);
    }

    /// Four f64 from an array: the reference guarantees the four values.
    #[target_feature(enable = "avx2,fma")]
    fn load(v: &[f64; LANES]) -> __m256d {
        #[allow(unsafe_code)]
        // SAFETY: `v` is four readable f64; loadu needs no alignment.
        unsafe {
            std::arch::x86_64::_mm256_loadu_pd(v.as_ptr())
        }
    }

    /// Four f32 widened to f64.
    #[target_feature(enable = "avx2,fma")]
    fn load_kernel(v: &[Kernel; LANES]) -> __m256d {
        #[allow(unsafe_code)]
        // SAFETY: `v` is four readable f32; loadu needs no alignment.
        let narrow = unsafe { std::arch::x86_64::_mm_loadu_ps(v.as_ptr()) };
        _mm256_cvtps_pd(narrow)
    }

    #[target_feature(enable = "avx2,fma")]
    fn store(to: &mut [f64; LANES], v: __m256d) {
        #[allow(unsafe_code)]
        // SAFETY: `to` is four writable f64; storeu needs no alignment.
        unsafe {
            std::arch::x86_64::_mm256_storeu_pd(to.as_mut_ptr(), v)
        }
    }

    /// The lane sums of `v[0] .. v[3]`, as one vector.
    #[target_feature(enable = "avx2,fma")]
    fn sums(v: &[__m256d; ROWS]) -> __m256d {
        let low = _mm256_hadd_pd(v[0], v[1]);
        let high = _mm256_hadd_pd(v[2], v[3]);
        _mm256_add_pd(
            _mm256_permute2f128_pd::<0x20>(low, high),
            _mm256_permute2f128_pd::<0x31>(low, high),
        )
    }

    #[target_feature(enable = "avx2,fma")]
    fn edge_product_avx2(
        m: usize,
        k: &[Kernel],
        xi: &[f64],
        xj: &[f64],
        oi: &mut [f64],
        oj: &mut [f64],
    ) {
        let p = padded(m);
        let (xi, xj) = (
            xi[..p].as_chunks::<LANES>().0,
            xj[..p].as_chunks::<LANES>().0,
        );
        let (oi, oj) = (
            oi[..p].as_chunks_mut::<LANES>().0,
            oj[..p].as_chunks_mut::<LANES>().0,
        );
        let mut start = 0;
        for q in 0..p / LANES {
            let len = p - q * LANES;
            let chunks = k[start..start + ROWS * len].as_chunks::<CHUNK>().0;
            start += ROWS * len;
            // Broadcasts of x_i[a] and x_j[a] for the block's rows `a`.
            let mut bi = [_mm256_setzero_pd(); ROWS];
            let mut bj = [_mm256_setzero_pd(); ROWS];
            for r in 0..ROWS {
                bi[r] = _mm256_set1_pd(xi[q][r]);
                bj[r] = _mm256_set1_pd(xj[q][r]);
            }
            let mut si = [_mm256_setzero_pd(); ROWS];
            let mut sj = [_mm256_setzero_pd(); ROWS];
            for ((((chunk, xi4), xj4), oi4), oj4) in chunks
                .iter()
                .zip(&xi[q..])
                .zip(&xj[q..])
                .zip(oi[q..].iter_mut())
                .zip(oj[q..].iter_mut())
            {
                let (vxi, vxj) = (load(xi4), load(xj4));
                let (mut voi, mut voj) = (load(oi4), load(oj4));
                let rows = chunk.as_chunks::<LANES>().0;
                for r in 0..ROWS {
                    let kv = load_kernel(&rows[r]);
                    si[r] = _mm256_fmadd_pd(kv, vxj, si[r]);
                    sj[r] = _mm256_fmadd_pd(kv, vxi, sj[r]);
                    voi = _mm256_fmadd_pd(kv, bj[r], voi);
                    voj = _mm256_fmadd_pd(kv, bi[r], voj);
                }
                store(oi4, voi);
                store(oj4, voj);
            }
            let (total_i, total_j) = (
                _mm256_add_pd(load(&oi[q]), sums(&si)),
                _mm256_add_pd(load(&oj[q]), sums(&sj)),
            );
            store(&mut oi[q], total_i);
            store(&mut oj[q], total_j);
        }
    }

    /// Eight f32, two rows' chunk, widened to f64.
    #[target_feature(enable = "avx512f,avx2,fma")]
    fn load_kernel_pair(v: &[Kernel; 2 * LANES]) -> __m512d {
        #[allow(unsafe_code)]
        // SAFETY: `v` is eight readable f32; loadu needs no alignment.
        let narrow = unsafe { std::arch::x86_64::_mm256_loadu_ps(v.as_ptr()) };
        _mm512_cvtps_pd(narrow)
    }

    /// The lower and upper four lanes added.
    #[target_feature(enable = "avx512f,avx2,fma")]
    fn fold(v: __m512d) -> __m256d {
        _mm256_add_pd(_mm512_castpd512_pd256(v), _mm512_extractf64x4_pd::<1>(v))
    }

    /// [`edge_product_avx2`] with two rows' chunk per 512-bit register:
    /// half the multiply-add instructions, which bound the AVX2 loop.
    #[target_feature(enable = "avx512f,avx2,fma")]
    fn edge_product_avx512(
        m: usize,
        k: &[Kernel],
        xi: &[f64],
        xj: &[f64],
        oi: &mut [f64],
        oj: &mut [f64],
    ) {
        let p = padded(m);
        let (xi, xj) = (
            xi[..p].as_chunks::<LANES>().0,
            xj[..p].as_chunks::<LANES>().0,
        );
        let (oi, oj) = (
            oi[..p].as_chunks_mut::<LANES>().0,
            oj[..p].as_chunks_mut::<LANES>().0,
        );
        let mut start = 0;
        for q in 0..p / LANES {
            let len = p - q * LANES;
            let chunks = k[start..start + ROWS * len].as_chunks::<CHUNK>().0;
            start += ROWS * len;
            // x_i[a] and x_j[a] of rows (a0, a0 + 1) and (a0 + 2, a0 + 3),
            // four lanes each.
            let pair = |x: &[f64; LANES], r: usize| {
                _mm512_insertf64x4::<1>(_mm512_set1_pd(x[r]), _mm256_set1_pd(x[r + 1]))
            };
            let (bi01, bi23) = (pair(&xi[q], 0), pair(&xi[q], 2));
            let (bj01, bj23) = (pair(&xj[q], 0), pair(&xj[q], 2));
            let (mut si01, mut si23) = (_mm512_setzero_pd(), _mm512_setzero_pd());
            let (mut sj01, mut sj23) = (_mm512_setzero_pd(), _mm512_setzero_pd());
            for ((((chunk, xi4), xj4), oi4), oj4) in chunks
                .iter()
                .zip(&xi[q..])
                .zip(&xj[q..])
                .zip(oi[q..].iter_mut())
                .zip(oj[q..].iter_mut())
            {
                let halves = chunk.as_chunks::<{ 2 * LANES }>().0;
                let (k01, k23) = (load_kernel_pair(&halves[0]), load_kernel_pair(&halves[1]));
                let vxi = _mm512_broadcast_f64x4(load(xi4));
                let vxj = _mm512_broadcast_f64x4(load(xj4));
                si01 = _mm512_fmadd_pd(k01, vxj, si01);
                si23 = _mm512_fmadd_pd(k23, vxj, si23);
                sj01 = _mm512_fmadd_pd(k01, vxi, sj01);
                sj23 = _mm512_fmadd_pd(k23, vxi, sj23);
                let to_i = _mm512_fmadd_pd(k23, bj23, _mm512_mul_pd(k01, bj01));
                let to_j = _mm512_fmadd_pd(k23, bi23, _mm512_mul_pd(k01, bi01));
                let (voi, voj) = (
                    _mm256_add_pd(load(oi4), fold(to_i)),
                    _mm256_add_pd(load(oj4), fold(to_j)),
                );
                store(oi4, voi);
                store(oj4, voj);
            }
            let halves = |v: __m512d| (_mm512_castpd512_pd256(v), _mm512_extractf64x4_pd::<1>(v));
            let ((s0, s1), (s2, s3)) = (halves(si01), halves(si23));
            let ((t0, t1), (t2, t3)) = (halves(sj01), halves(sj23));
            let (total_i, total_j) = (
                _mm256_add_pd(load(&oi[q]), sums(&[s0, s1, s2, s3])),
                _mm256_add_pd(load(&oj[q]), sums(&[t0, t1, t2, t3])),
            );
            store(&mut oi[q], total_i);
            store(&mut oj[q], total_j);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The product of one human edge written from its definition, with K
    /// read through `block_slot`.
    fn reference(m: usize, k: &[Kernel], xi: &[f64], xj: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let entry = |a: usize, b: usize| match a.cmp(&b) {
            std::cmp::Ordering::Less => f64::from(k[block_slot(a, b, m)]),
            std::cmp::Ordering::Greater => f64::from(k[block_slot(b, a, m)]),
            std::cmp::Ordering::Equal => 0.0,
        };
        let row = |a: usize, x: &[f64]| (0..m).map(|b| entry(a, b) * x[b]).sum::<f64>();
        (
            (0..m).map(|a| row(a, xj)).collect(),
            (0..m).map(|a| row(a, xi)).collect(),
        )
    }

    /// A table row with padding zero, as `extend_kernel_row` makes it.
    fn case(m: usize) -> (Vec<Kernel>, Vec<f64>, Vec<f64>) {
        let k = block_slots(m)
            .iter()
            .enumerate()
            .map(|(t, slot)| slot.map_or(0.0, |_| 0.05 + (t as f64 * 0.377).fract() as Kernel))
            .collect();
        let p = padded(m);
        let x = |phase: f64, scale: f64| -> Vec<f64> {
            (0..p)
                .map(|t| {
                    if t < m {
                        phase + (t as f64 * scale).fract()
                    } else {
                        0.0
                    }
                })
                .collect()
        };
        (k, x(0.1, 0.618), x(0.2, 0.414))
    }

    fn close(got: &[f64], want: &[f64], offset: f64) {
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g - offset - w).abs() <= 1e-12 * w.abs().max(1.0),
                "{g} vs {w}"
            );
        }
    }

    #[test]
    fn the_layout_holds_every_robot_edge_once() {
        for m in 0..=13 {
            let slots = block_slots(m);
            let edges: Vec<(usize, usize)> = slots.iter().flatten().copied().collect();
            assert_eq!(edges.len(), m * m.saturating_sub(1) / 2, "m = {m}");
            for a in 0..m {
                for b in a + 1..m {
                    assert_eq!(slots[block_slot(a, b, m)], Some((a, b)), "m = {m}");
                }
            }
        }
    }

    #[test]
    fn both_code_paths_equal_the_definition_at_every_size() {
        // Sizes around the block of rows and the lanes, and beyond.
        for m in (0..=13).chain([31, 32, 33, 64]) {
            let (k, xi, xj) = case(m);
            let (want_i, want_j) = reference(m, &k, &xi, &xj);
            let p = padded(m);
            let (mut oi, mut oj) = (vec![1.0; p], vec![2.0; p]);
            edge_product_with(m, &k, &xi, &xj, &mut oi, &mut oj);
            close(&oi[..m], &want_i, 1.0);
            close(&oj[..m], &want_j, 2.0);
            let (mut oi, mut oj) = (vec![1.0; p], vec![2.0; p]);
            edge_product(m, &k, &xi, &xj, &mut oi, &mut oj);
            close(&oi[..m], &want_i, 1.0);
            close(&oj[..m], &want_j, 2.0);
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn the_avx2_path_agrees_with_the_baseline() {
        if !crate::cpu::avx2_fma() {
            return;
        }
        for m in [5, 37] {
            let (k, xi, xj) = case(m);
            let p = padded(m);
            let (mut bi, mut bj) = (vec![1.0; p], vec![2.0; p]);
            edge_product_with(m, &k, &xi, &xj, &mut bi, &mut bj);
            let (mut oi, mut oj) = (vec![1.0; p], vec![2.0; p]);
            assert!(simd::edge_product(m, &k, &xi, &xj, &mut oi, &mut oj));
            close(&oi, &bi, 0.0);
            close(&oj, &bj, 0.0);
            if crate::cpu::avx512() {
                let (mut oi, mut oj) = (vec![1.0; p], vec![2.0; p]);
                assert!(simd::edge_product_512(m, &k, &xi, &xj, &mut oi, &mut oj));
                close(&oi, &bi, 0.0);
                close(&oj, &bj, 0.0);
            }
        }
        let lengths: Vec<f64> = (0..50)
            .map(|t| t as f64 * 0.013)
            .chain([f64::INFINITY])
            .collect();
        let (mut plain, mut dispatched) = (Vec::new(), Vec::new());
        extend_kernel_row_with::<false>(&mut plain, 0.3, &lengths, 0.01);
        assert!(simd::extend_kernel_row(
            &mut dispatched,
            0.3,
            &lengths,
            0.01
        ));
        if crate::cpu::avx512() {
            let mut wide = Vec::new();
            assert!(simd::extend_kernel_row_512(&mut wide, 0.3, &lengths, 0.01));
            assert_eq!(wide, dispatched);
        }
        // Fused multiply-adds may move the f32 rounding by an ulp.
        for (p, d) in plain.iter().zip(&dispatched) {
            assert!((p - d).abs() <= 1.2e-7 * p, "{p} vs {d}");
        }
        assert_eq!(dispatched.last(), Some(&0.0));
    }

    #[test]
    fn kernel_values_are_the_definition_rounded_to_f32() {
        let lengths: Vec<f64> = (0..2000).map(|t| t as f64 * 0.0007).collect();
        let mut row = Vec::new();
        extend_kernel_row(&mut row, 0.6, &lengths, 0.01);
        for (&got, &f) in row.iter().zip(&lengths) {
            let want = (-(0.6 - f) * (0.6 - f) / 0.01).exp();
            // f32 rounding: half an ulp, 2^-24 relative, plus subnormals.
            assert!(
                (f64::from(got) - want).abs() <= 6.0e-8 * want + 1e-45,
                "{got} vs {want}"
            );
        }
        extend_kernel_row(&mut row, 0.6, &[f64::INFINITY], 0.01);
        assert_eq!(row.last(), Some(&0.0));
    }
}
