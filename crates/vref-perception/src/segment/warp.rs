//! The support's own warp. A depth camera's error is not only noise: its
//! depth scale can drift smoothly across the image (a headset's by 5-6 %
//! on the rendered scenes), which lifts a far floor's edge above the
//! plane's tolerance, where it seeds objects or joins the objects
//! standing there. The warp is modelled as a smooth relative depth error,
//! `z (1 + w(u, v))` with `w` a quadratic in the image's coordinates, so a
//! reading's height above the plane errs by `z (n . ray) w(u, v)`; it is
//! fitted to the readings near the support, whose band follows the fit
//! round by round so that a lifted edge joins it, and only the lift is
//! taken off: where the fit puts the support below the plane, heights stay
//! as they are (a support fitted through its own noise would seed half of
//! it).

/// Terms of the quadratic: 1, x, y, x^2, x y, y^2.
const TERMS: usize = 6;
/// Rounds of the fit, each over the readings near the last one's surface.
const ROUNDS: usize = 4;
/// Fewer sampled readings near the support than this fit nothing.
const MIN_SAMPLES: usize = 50;

/// What the fit reads, per pixel and per row and column.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Support<'a> {
    /// Depth in metres, 0 where there is no reading.
    pub z: &'a [f32],
    /// Each column's and row's ray slope (`(u - cx) / fx`, `(v - cy) / fy`).
    pub xu: &'a [f32],
    pub yv: &'a [f32],
    /// The plane's unit normal.
    pub normal: [f32; 3],
    /// A reading within `band` times `tolerance z^2` of the surface is on
    /// the support.
    pub tolerance: f32,
    pub band: f32,
    /// Every `stride`-th pixel of every `stride`-th row is sampled.
    pub stride: usize,
}

impl Support<'_> {
    fn width(&self) -> usize {
        self.xu.len()
    }

    /// The terms at pixel (u, v), each times the height's change per unit
    /// of relative depth error there.
    fn terms(&self, u: usize, v: usize) -> [f64; TERMS] {
        let (w, h) = (self.xu.len() as f64, self.yv.len() as f64);
        let x = 2.0 * u as f64 / w - 1.0;
        let y = 2.0 * v as f64 / h - 1.0;
        let n = self.normal;
        let per_depth = f64::from(self.z[v * self.xu.len() + u])
            * f64::from(n[0] * self.xu[u] + n[1] * self.yv[v] + n[2]);
        [1.0, x, y, x * x, x * y, y * y].map(|t| t * per_depth)
    }
}

fn dot(a: &[f64; TERMS], b: &[f64; TERMS]) -> f64 {
    a.iter().zip(b).map(|(p, q)| p * q).sum()
}

/// Solves `a x = b` by Gaussian elimination with partial pivoting; `None`
/// when `a` is singular.
fn solve(mut a: [[f64; TERMS]; TERMS], mut b: [f64; TERMS]) -> Option<[f64; TERMS]> {
    for col in 0..TERMS {
        let pivot = (col..TERMS).max_by(|&p, &q| a[p][col].abs().total_cmp(&a[q][col].abs()))?;
        a.swap(col, pivot);
        b.swap(col, pivot);
        if a[col][col].abs() < 1e-12 {
            return None;
        }
        let (top, below) = a.split_at_mut(col + 1);
        let pivot_row = &top[col];
        for (offset, row) in below.iter_mut().enumerate() {
            let f = row[col] / pivot_row[col];
            for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= f * p;
            }
            b[col + 1 + offset] -= f * b[col];
        }
    }
    let mut x = [0.0; TERMS];
    for row in (0..TERMS).rev() {
        let rest: f64 = (row + 1..TERMS).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - rest) / a[row][row];
    }
    Some(x)
}

/// The warp's coefficients fitted to `height` (above the plane, 0 where
/// there is no reading); `None` with too few readings near the support.
fn fit(s: &Support<'_>, height: &[f32]) -> Option<[f64; TERMS]> {
    let w = s.width();
    let h = s.yv.len();
    let stride = s.stride.max(1);
    let mut c = [0.0; TERMS];
    for _ in 0..ROUNDS {
        let mut a = [[0.0; TERMS]; TERMS];
        let mut b = [0.0; TERMS];
        let mut samples = 0;
        for v in (0..h).step_by(stride) {
            for u in (0..w).step_by(stride) {
                let i = v * w + u;
                let z = s.z[i];
                if z <= 0.0 {
                    continue;
                }
                let t = s.terms(u, v);
                let r = f64::from(height[i]);
                if (r - dot(&t, &c)).abs() > f64::from(s.band * s.tolerance * z * z) {
                    continue;
                }
                samples += 1;
                for p in 0..TERMS {
                    b[p] += t[p] * r;
                    for q in 0..TERMS {
                        a[p][q] += t[p] * t[q];
                    }
                }
            }
        }
        if samples < MIN_SAMPLES {
            return None;
        }
        c = solve(a, b)?;
    }
    Some(c)
}

/// Takes the support's lift off `height`; 0 `band` leaves it as it is.
pub(crate) fn flatten(s: &Support<'_>, height: &mut [f32]) {
    if s.band <= 0.0 {
        return;
    }
    let Some(c) = fit(s, height) else {
        return;
    };
    // Row by row, the quadratic is A + B x + C x^2 in the column's x.
    let w = s.width();
    let h = s.yv.len();
    let dx = 2.0 / w as f64;
    let n = s.normal;
    for v in 0..h {
        let y = 2.0 * v as f64 / h as f64 - 1.0;
        let (a, b, c2) = (c[0] + c[2] * y + c[5] * y * y, c[1] + c[4] * y, c[3]);
        let ray_y = n[1] * s.yv[v] + n[2];
        let row = v * w;
        for u in 0..w {
            let z = s.z[row + u];
            if z <= 0.0 {
                continue;
            }
            let x = u as f64 * dx - 1.0;
            let per_depth = f64::from(z * (n[0] * s.xu[u] + ray_y));
            let lift = (per_depth * (a + x * (b + x * c2))).max(0.0);
            height[row + u] -= lift as f32;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A floor 2 m below a camera looking down, its depth scaled by
    /// `1 + 0.05 x` across the image (x from -1 to 1), with a box of
    /// 10 cm in the middle.
    fn warped_floor() -> (Vec<f32>, Vec<f32>, Vec<f32>, Vec<f32>) {
        let (w, h) = (64usize, 48usize);
        let xu: Vec<f32> = (0..w).map(|u| (u as f32 - 32.0) / 50.0).collect();
        let yv: Vec<f32> = (0..h).map(|v| (v as f32 - 24.0) / 50.0).collect();
        let mut z = vec![0.0; w * h];
        let mut height = vec![0.0; w * h];
        for v in 0..h {
            for u in 0..w {
                let x = 2.0 * u as f32 / w as f32 - 1.0;
                let in_box = (28..36).contains(&u) && (20..28).contains(&v);
                let true_z = if in_box { 1.9 } else { 2.0 };
                let i = v * w + u;
                z[i] = true_z * (1.0 + 0.05 * x);
                // Height above the plane z = 2 (normal (0, 0, -1), offset 2):
                // 2 - z.
                height[i] = 2.0 - z[i];
            }
        }
        (z, xu, yv, height)
    }

    fn support<'a>(z: &'a [f32], xu: &'a [f32], yv: &'a [f32], band: f32) -> Support<'a> {
        Support {
            z,
            xu,
            yv,
            normal: [0.0, 0.0, -1.0],
            tolerance: 0.01,
            band,
            stride: 2,
        }
    }

    #[test]
    fn the_lifted_side_of_a_warped_floor_comes_down_and_the_box_stays() {
        let (z, xu, yv, height) = warped_floor();
        let w = xu.len();
        let lifted_edge = 10 * w + 2;
        assert!(
            height[lifted_edge] > 0.08,
            "the warp lifts one side by about 9 cm"
        );
        let mut flat = height.clone();
        flatten(&support(&z, &xu, &yv, 3.0), &mut flat);
        assert!(flat[lifted_edge].abs() < 0.01, "{}", flat[lifted_edge]);
        let in_box = 24 * w + 32;
        assert!((flat[in_box] - 0.1).abs() < 0.02, "{}", flat[in_box]);
        // The side the warp lowers is left as it is.
        let lowered_edge = 10 * w + w - 3;
        assert_eq!(flat[lowered_edge], height[lowered_edge]);
        let mut same = height.clone();
        flatten(&support(&z, &xu, &yv, 0.0), &mut same);
        assert_eq!(same, height);
    }
}
