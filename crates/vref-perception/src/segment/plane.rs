//! The supporting plane: RANSAC on a sparse grid of readings, then a
//! least-squares refit on the inliers. Deterministic: the sampler is a
//! seeded SplitMix64, so the same frame and seed give the same plane.

/// A plane `n . p + d = 0` in the camera frame (metres), `n` of unit
/// length and pointing to the camera's side (`d > 0`): `n . p + d` is a
/// point's height above the plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    pub normal: [f64; 3],
    pub offset: f64,
    /// Share of the sampled readings within the tolerance of the plane.
    pub share: f64,
}

impl Plane {
    pub fn height(&self, p: [f64; 3]) -> f64 {
        dot(self.normal, p) + self.offset
    }
}

/// SplitMix64 (Steele, Lea, Flood 2014): small, fast, and the same on
/// every platform.
#[derive(Debug, Clone)]
pub(crate) struct SplitMix(u64);

impl SplitMix {
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n` > 0); the multiply-shift bias is below
    /// 2^-32 for the sizes used here.
    pub(crate) fn below(&mut self, n: usize) -> usize {
        (((self.next() >> 32) * n as u64) >> 32) as usize
    }
}

/// One sampled reading: the point and its plane tolerance.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Sample {
    pub p: [f32; 3],
    pub tolerance: f32,
}

/// The best plane through `samples` (at least 3), or `None` when every
/// hypothesis was degenerate. `share` counts the final inliers.
pub(crate) fn fit(samples: &[Sample], iterations: u32, seed: u64) -> Option<Plane> {
    let n = samples.len();
    if n < 3 {
        return None;
    }
    let mut rng = SplitMix::new(seed);
    let mut best: Option<([f32; 3], f32)> = None;
    let mut best_count = 0usize;
    for _ in 0..iterations {
        let (i, j, k) = (rng.below(n), rng.below(n), rng.below(n));
        if i == j || j == k || i == k {
            continue;
        }
        let (a, b, c) = (samples[i].p, samples[j].p, samples[k].p);
        let normal = cross(sub(b, a), sub(c, a));
        let length = dot(normal, normal).sqrt();
        // Nearly collinear points give a normal of noise.
        let span = dot(sub(b, a), sub(b, a)).max(dot(sub(c, a), sub(c, a)));
        // (NaN from overflowing coordinates fails the test too.)
        if length.is_nan() || length <= 1e-3 * span || length == 0.0 {
            continue;
        }
        let normal = normal.map(|x| x / length);
        let offset = -dot(normal, a);
        let count = samples
            .iter()
            .filter(|s| (dot(normal, s.p) + offset).abs() <= s.tolerance)
            .count();
        if count > best_count {
            best_count = count;
            best = Some((normal, offset));
        }
    }
    let (mut normal, mut offset) = best?;
    // Two refits: the first moves the plane off the three sampled points'
    // noise, the second settles which readings are inliers of that.
    let mut count = best_count;
    for _ in 0..2 {
        let Some((n2, d2, c2)) = refit(samples, normal, offset) else {
            break;
        };
        (normal, offset, count) = (n2, d2, c2);
    }
    let (mut normal, mut offset) = (normal.map(f64::from), f64::from(offset));
    if offset < 0.0 {
        normal = normal.map(|x| -x);
        offset = -offset;
    }
    Some(Plane {
        normal,
        offset,
        share: count as f64 / n as f64,
    })
}

/// Least squares on the inliers of `(normal, offset)`: the plane through
/// their centroid normal to the direction of least spread. Returns the
/// new plane and how many samples are its inliers.
fn refit(samples: &[Sample], normal: [f32; 3], offset: f32) -> Option<([f32; 3], f32, usize)> {
    let inlier = |s: &&Sample| (dot(normal, s.p) + offset).abs() <= s.tolerance;
    let mut sum = [0f64; 3];
    let mut count = 0usize;
    for s in samples.iter().filter(inlier) {
        for (acc, x) in sum.iter_mut().zip(s.p) {
            *acc += f64::from(x);
        }
        count += 1;
    }
    if count < 3 {
        return None;
    }
    let mean = sum.map(|s| s / count as f64);
    let mut cov = [[0f64; 3]; 3];
    for s in samples.iter().filter(inlier) {
        let q = [0, 1, 2].map(|i| f64::from(s.p[i]) - mean[i]);
        for (i, row) in cov.iter_mut().enumerate() {
            for (j, c) in row.iter_mut().enumerate() {
                *c += q[i] * q[j];
            }
        }
    }
    let mut fitted = smallest_eigenvector(cov)?;
    if dot(fitted, normal.map(f64::from)) < 0.0 {
        fitted = fitted.map(|x| -x);
    }
    let n32 = fitted.map(|x| x as f32);
    let d32 = -dot(fitted, mean) as f32;
    let inliers = samples
        .iter()
        .filter(|s| (dot(n32, s.p) + d32).abs() <= s.tolerance)
        .count();
    Some((n32, d32, inliers))
}

/// The unit eigenvector of the smallest eigenvalue of a symmetric 3x3
/// matrix, by cyclic Jacobi rotations (exact to rounding in a few sweeps
/// for 3x3, and well defined for a singular matrix, where a perfect
/// plane's covariance is).
fn smallest_eigenvector(mut a: [[f64; 3]; 3]) -> Option<[f64; 3]> {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..32 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off <= 1e-30 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() <= 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in &mut a {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (row_p, row_q) = (a[p], a[q]);
            for (k, (apk, aqk)) in row_p.into_iter().zip(row_q).enumerate() {
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let smallest = (0..3).min_by(|&i, &j| a[i][i].total_cmp(&a[j][j]))?;
    let e = [v[0][smallest], v[1][smallest], v[2][smallest]];
    let length = dot(e, e).sqrt();
    (length.is_finite() && length > 0.0).then(|| e.map(|x| x / length))
}

fn dot<T: Copy + std::ops::Mul<Output = T> + std::ops::Add<Output = T>>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn jacobi_finds_the_flat_direction() {
        // Spread along x and y, none along (0, 0, 1).
        let cov = [[4.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 0.0]];
        let e = smallest_eigenvector(cov).unwrap();
        assert!((e[2].abs() - 1.0).abs() < 1e-9, "{e:?}");
    }

    #[test]
    fn sampler_is_uniform_enough_and_in_range() {
        let mut rng = SplitMix::new(7);
        let mut counts = [0u32; 5];
        for _ in 0..50_000 {
            counts[rng.below(5)] += 1;
        }
        assert!(
            counts.iter().all(|&c| (9_000..11_000).contains(&c)),
            "{counts:?}"
        );
    }
}
