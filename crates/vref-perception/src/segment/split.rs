//! Where what stands on the plane is cut apart: depth jumps (one surface
//! in front of another), concave creases (two surfaces meeting, like a
//! box standing on another or two boxes side by side), and colour edges
//! where the geometry alone is unsure.

use super::normals::sub;

/// What the cut test reads, all of the image's size.
#[derive(Debug)]
pub(crate) struct CutInput<'a> {
    pub z: &'a [f32],
    pub smooth: &'a [f32],
    pub normals: &'a [[f32; 3]],
    pub xu: &'a [f32],
    pub yv: &'a [f32],
    pub rgb: &'a [u8],
    pub width: usize,
    pub height: usize,
}

/// The largest depth step between neighbouring raw readings at depth `z`
/// that is still one surface: `jump_ratio` of the depth, or four sigmas
/// of the difference of two readings' noise where that is more. The
/// plane's `tolerance` is four sigmas of one reading at 1 m, growing with
/// `z^2`, so the difference's four sigmas are `sqrt(2) tolerance z^2`: at
/// the reference camera's 1 m that is below the ratio, at its 4 m (1 %
/// noise per reading) over twice it, where the ratio alone cut far
/// objects into pieces.
pub(crate) fn jump_limit(z: f32, ratio: f32, tolerance: f32) -> f32 {
    z * ratio.max(std::f32::consts::SQRT_2 * tolerance * z)
}

/// Thresholds of the cut test.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CutRule {
    pub jump_ratio: f32,
    /// The plane tolerance at 1 m: the depth noise law, for [`jump_limit`].
    pub tolerance: f32,
    pub crease: f32,
    pub weak_crease: f32,
    pub crease_step: usize,
    pub colour_edge: f32,
}

/// Marks `cut[i]` for every pixel in `candidate` that lies on a jump, a
/// crease or a confirmed colour edge.
pub(crate) fn cuts(input: &CutInput<'_>, rule: CutRule, candidate: &[bool], cut: &mut [bool]) {
    let CutInput {
        z,
        smooth,
        normals,
        xu,
        yv,
        rgb,
        width,
        height,
    } = *input;
    let s = rule.crease_step;
    let point = |i: usize, u: usize, v: usize| {
        let d = smooth[i];
        [xu[u] * d, yv[v] * d, d]
    };
    // How much the normals at i and j turn towards each other, along the
    // direction from i to j: negative on a concave crease.
    let concavity = |i: usize, j: usize, (ui, vi): (usize, usize), (uj, vj): (usize, usize)| {
        let (a, b) = (normals[i], normals[j]);
        if a == [0.0; 3] || b == [0.0; 3] {
            return 0.0;
        }
        let d = sub(point(j, uj, vj), point(i, ui, vi));
        let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        // Across a large depth jump the two normals belong to unrelated
        // surfaces; the jump test cuts there.
        let step = (smooth[j] - smooth[i]).abs();
        if length.is_nan()
            || length <= 0.0
            || step > rule.jump_ratio * smooth[i].min(smooth[j]) * (2 * s) as f32
        {
            return 0.0;
        }
        ((b[0] - a[0]) * d[0] + (b[1] - a[1]) * d[1] + (b[2] - a[2]) * d[2]) / length
    };
    let colour = |i: usize, j: usize| {
        let (a, b) = (&rgb[3 * i..3 * i + 3], &rgb[3 * j..3 * j + 3]);
        let diff: u32 = a
            .iter()
            .zip(b)
            .map(|(&x, &y)| u32::from(x.abs_diff(y)))
            .sum();
        diff as f32 / 3.0
    };
    for v in 0..height {
        for u in 0..width {
            let i = v * width + u;
            cut[i] = false;
            if !candidate[i] {
                continue;
            }
            let z0 = z[i];
            let limit = jump_limit(z0, rule.jump_ratio, rule.tolerance);
            let mut weak = false;
            // Jumps: to each neighbour, and between the neighbours either
            // side, which a flying pixel between two surfaces bridges in
            // two smaller steps.
            let mut jump = |a: usize, b: usize, span: f32| {
                let (za, zb) = (z[a], z[b]);
                if za > 0.0 && zb > 0.0 {
                    let step = (za - zb).abs();
                    if step > limit * span {
                        return 2;
                    }
                    if step > 0.5 * limit * span {
                        weak = true;
                    }
                }
                0
            };
            let mut strong = 0;
            if u >= 1 && u + 1 < width {
                strong += jump(i - 1, i, 1.0) + jump(i, i + 1, 1.0) + jump(i - 1, i + 1, 2.0);
            }
            if v >= 1 && v + 1 < height {
                strong += jump(i - width, i, 1.0)
                    + jump(i, i + width, 1.0)
                    + jump(i - width, i + width, 2.0);
            }
            if strong > 0 {
                cut[i] = true;
                continue;
            }
            let mut crease = 0f32;
            if u >= s && u + s < width {
                crease = crease.min(concavity(i - s, i + s, (u - s, v), (u + s, v)));
            }
            if v >= s && v + s < height {
                crease = crease.min(concavity(
                    i - s * width,
                    i + s * width,
                    (u, v - s),
                    (u, v + s),
                ));
            }
            if crease < -rule.crease {
                cut[i] = true;
                continue;
            }
            weak |= crease < -rule.weak_crease;
            if weak && u >= 1 && u + 1 < width && v >= 1 && v + 1 < height {
                let edge = colour(i - 1, i + 1).max(colour(i - width, i + width));
                if edge > rule.colour_edge {
                    cut[i] = true;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::jump_limit;

    #[test]
    fn the_jump_limit_is_the_ratio_near_and_the_noise_far() {
        let (ratio, tolerance) = (0.02, 0.01);
        // At 1 m the noise's four sigmas (1.4 % of depth) are below the ratio.
        assert_eq!(jump_limit(1.0, ratio, tolerance), 0.02);
        assert_eq!(jump_limit(0.5, ratio, tolerance), 0.5 * 0.02);
        // At 4 m one reading errs by 1 % of its depth: a 4 % step between
        // neighbours (2.8 sigmas of their difference) is noise, not a jump;
        // a 6 % one is.
        let limit = jump_limit(4.0, ratio, tolerance);
        assert!(limit > 0.04 * 4.0 && limit < 0.06 * 4.0, "{limit}");
    }
}
