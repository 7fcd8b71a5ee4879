//! Surface normals from smoothed depth. Kinect-class depth is quantised
//! (millimetres at 1 m, centimetres at 3 m), so a normal from neighbouring
//! raw readings is mostly quantisation noise; a box filter over the
//! surface's own readings, then differences a few pixels apart, leave the
//! shape.

/// Scratch of the box filter, sized to the image once.
#[derive(Debug, Default)]
pub(crate) struct BoxScratch {
    sums: Vec<f32>,
    counts: Vec<f32>,
    column_sums: Vec<f32>,
    column_counts: Vec<f32>,
}

impl BoxScratch {
    pub(crate) fn resize(&mut self, width: usize, height: usize) {
        self.sums.resize(width * height, 0.0);
        self.counts.resize(width * height, 0.0);
        self.column_sums.resize(width, 0.0);
        self.column_counts.resize(width, 0.0);
    }

    pub(crate) fn capacity(&self) -> usize {
        self.sums.capacity() + self.counts.capacity() + self.column_sums.capacity()
    }
}

/// Box-filters `z` (radius `r`) over the pixels where `keep` is true:
/// others neither contribute nor receive (`out` is 0 there), so a surface
/// is not bent towards what lies behind its outline. Running sums, so the
/// cost does not grow with `r`.
pub(crate) fn smooth(
    z: &[f32],
    keep: &[bool],
    width: usize,
    height: usize,
    r: usize,
    scratch: &mut BoxScratch,
    out: &mut [f32],
) {
    let BoxScratch {
        sums,
        counts,
        column_sums,
        column_counts,
    } = scratch;
    for v in 0..height {
        let row = v * width;
        let (zr, kr) = (&z[row..row + width], &keep[row..row + width]);
        let (sr, cr) = (&mut sums[row..row + width], &mut counts[row..row + width]);
        let (mut s, mut c) = (0f32, 0f32);
        for u in 0..r.min(width) {
            if kr[u] {
                s += zr[u];
                c += 1.0;
            }
        }
        for u in 0..width {
            if u + r < width && kr[u + r] {
                s += zr[u + r];
                c += 1.0;
            }
            sr[u] = s;
            cr[u] = c;
            if u >= r && kr[u - r] {
                s -= zr[u - r];
                c -= 1.0;
            }
        }
    }
    column_sums.fill(0.0);
    column_counts.fill(0.0);
    let add_row = |v: usize, sign: f32, cs: &mut [f32], cc: &mut [f32]| {
        let row = v * width;
        for ((a, b), (s, c)) in cs
            .iter_mut()
            .zip(cc.iter_mut())
            .zip(sums[row..row + width].iter().zip(&counts[row..row + width]))
        {
            *a += sign * s;
            *b += sign * c;
        }
    };
    for v in 0..r.min(height) {
        add_row(v, 1.0, column_sums, column_counts);
    }
    for v in 0..height {
        if v + r < height {
            add_row(v + r, 1.0, column_sums, column_counts);
        }
        let row = v * width;
        for u in 0..width {
            let i = row + u;
            out[i] = if keep[i] && column_counts[u] > 0.5 {
                column_sums[u] / column_counts[u]
            } else {
                0.0
            };
        }
        if v >= r {
            add_row(v - r, -1.0, column_sums, column_counts);
        }
    }
}

/// The unit normal at every pixel with a smoothed depth, facing the
/// camera; `[0, 0, 0]` where it cannot be taken. Differences span
/// `step` pixels either side, one-sided at an outline; a difference
/// across a depth jump (more than `jump_ratio` of the depth per pixel)
/// is no surface and gives no normal.
#[allow(clippy::too_many_arguments)]
pub(crate) fn normals(
    smooth: &[f32],
    xu: &[f32],
    yv: &[f32],
    width: usize,
    height: usize,
    step: usize,
    jump_ratio: f32,
    out: &mut [[f32; 3]],
) {
    let point = |u: usize, v: usize| {
        let z = smooth[v * width + u];
        [xu[u] * z, yv[v] * z, z]
    };
    // The two points a difference along one axis is taken between,
    // nearer ones where the farther lie off the surface.
    let ends = |z0: f32, before: Option<usize>, after: Option<usize>, at: &dyn Fn(usize) -> f32| {
        let ok = |k: Option<usize>| k.filter(|&k| at(k) > 0.0);
        let (b, a) = (ok(before), ok(after));
        let limit = jump_ratio * z0 * step as f32;
        let near = |k: Option<usize>| k.filter(|&k| (at(k) - z0).abs() <= limit);
        (near(b), near(a))
    };
    for v in 0..height {
        for u in 0..width {
            let i = v * width + u;
            let z0 = smooth[i];
            out[i] = [0.0; 3];
            if z0 <= 0.0 {
                continue;
            }
            let row = |k: usize| smooth[v * width + k];
            let col = |k: usize| smooth[k * width + u];
            let (l, r) = ends(
                z0,
                u.checked_sub(step),
                Some(u + step).filter(|&k| k < width),
                &row,
            );
            let (t, b) = ends(
                z0,
                v.checked_sub(step),
                Some(v + step).filter(|&k| k < height),
                &col,
            );
            let dx = match (l, r) {
                (Some(l), Some(r)) => sub(point(r, v), point(l, v)),
                (None, Some(r)) => sub(point(r, v), point(u, v)),
                (Some(l), None) => sub(point(u, v), point(l, v)),
                (None, None) => continue,
            };
            let dy = match (t, b) {
                (Some(t), Some(b)) => sub(point(u, b), point(u, t)),
                (None, Some(b)) => sub(point(u, b), point(u, v)),
                (Some(t), None) => sub(point(u, v), point(u, t)),
                (None, None) => continue,
            };
            let n = cross(dx, dy);
            let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            if length.is_nan() || length <= 0.0 {
                continue;
            }
            // x right, y down: dx x dy points away from the camera.
            out[i] = n.map(|c| -c / length);
        }
    }
}

pub(crate) fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
