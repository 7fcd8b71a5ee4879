//! A second view of one capture, for checking matching across viewpoints
//! on real readings: the frame's points seen from a virtual camera
//! walked around the table (about the supporting plane's normal, through
//! the centre of what stands on it), z-buffered, each reading keeping its
//! own depth and colour. The real sensor's noise, holes and flying pixels
//! stay, and what the first camera never saw is a hole. What a second
//! sensor adds (its own depth noise, colour response and image size) can
//! be put on the view ([`SecondSensor`]). Every pixel of the view knows
//! the reading it shows, which is the truth a match of the two views is
//! scored against.

use image::{Luma, Rgb, RgbImage};

use crate::segment::{LabelImage, NoSupport, RgbdFrame, Segmentation, Segmenter};
use crate::{DepthImage, DepthPixels, Intrinsics, SegmentError, SegmentationSettings};

/// Why a frame has no second view.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReprojectError {
    #[error("segmenting the frame")]
    Segment(#[from] SegmentError),
    #[error("no supporting plane to walk around ({0})")]
    NoSupport(NoSupport),
    #[error("nothing stands on the supporting plane")]
    NothingOnIt,
    #[error("the view's scale {0} is not in (0, 1]")]
    Scale(f64),
    #[error("the object to move has no reading on the frame")]
    NothingToMove,
    #[error("the moved object would land within {0} m of another")]
    NotFree(f64),
}

/// Where the virtual camera stands, the image it takes, and what moved
/// before it looked.
#[derive(Debug, Clone, Copy)]
pub struct Walk<'a> {
    /// The turn about the supporting plane's normal, in degrees.
    pub yaw_deg: f64,
    /// Its image over the frame's, each way, in (0, 1]: a second camera
    /// of coarser resolution (focal lengths and principal point scaled
    /// alike).
    pub scale: f64,
    pub moved: Option<Moved<'a>>,
}

/// One object moved along the supporting plane, away from the centre of
/// what stands on it, before the view is taken: the object that moved
/// between the two views.
#[derive(Debug, Clone, Copy)]
pub struct Moved<'a> {
    /// Which of the frame's pixels (row-major) are its readings.
    pub readings: &'a [bool],
    /// How far it moves, in metres.
    pub metres: f64,
}

/// A moved object lands no nearer than this (metres, along the plane) to
/// any reading of another object: a free place.
pub const FREE: f64 = 0.1;

/// The virtual view of a frame.
#[derive(Debug, Clone)]
pub struct Reprojection {
    /// The virtual camera: the frame's, its image scaled ([`Walk::scale`]).
    pub intrinsics: Intrinsics,
    pub colour: RgbImage,
    pub depth: DepthPixels,
    /// For every pixel (row-major), the index of the frame's pixel it
    /// shows; `None` for a hole.
    pub source: Vec<Option<u32>>,
}

/// `colour` and `depth` (taken with `intrinsics`) seen from their camera
/// turned `yaw_deg` about the supporting plane's normal through the
/// centroid of the readings vref's segmenter puts on it; the same camera
/// model, the depth in the frame's units.
pub fn reproject(
    colour: &RgbImage,
    depth: &DepthImage,
    intrinsics: Intrinsics,
    yaw_deg: f64,
) -> Result<Reprojection, ReprojectError> {
    let walk = Walk {
        yaw_deg,
        scale: 1.0,
        moved: None,
    };
    reproject_walked(colour, depth, intrinsics, &walk)
}

/// [`reproject`] as `walk` says: at its yaw, into its camera, with its
/// object moved.
pub fn reproject_walked(
    colour: &RgbImage,
    depth: &DepthImage,
    intrinsics: Intrinsics,
    walk: &Walk<'_>,
) -> Result<Reprojection, ReprojectError> {
    let (yaw_deg, scale) = (walk.yaw_deg, walk.scale);
    if !(scale > 0.0 && scale <= 1.0) {
        return Err(ReprojectError::Scale(scale));
    }
    let mut labels = LabelImage::new(1, 1);
    let frame = RgbdFrame {
        colour,
        depth,
        intrinsics,
        up: None,
    };
    let plane =
        match Segmenter::new(SegmentationSettings::default()).segment(&frame, &mut labels)? {
            Segmentation::Objects { plane, .. } => plane,
            Segmentation::NoSupport(why) => return Err(ReprojectError::NoSupport(why)),
        };
    let (w, h) = colour.dimensions();
    let metres = depth.metres_per_unit();
    let raw = depth.pixels();
    let point = |u: u32, v: u32| -> Option<[f64; 3]> {
        let z = f64::from(raw.get_pixel(u, v).0[0]) * metres;
        (z > 0.0).then(|| intrinsics.back_project(f64::from(u), f64::from(v), z))
    };
    let mut sum = [0.0; 3];
    let mut count = 0.0;
    for (u, v, l) in labels.enumerate_pixels() {
        if let (true, Some(p)) = (l.0[0] > 0, point(u, v)) {
            (0..3).for_each(|k| sum[k] += p[k]);
            count += 1.0;
        }
    }
    if count == 0.0 {
        return Err(ReprojectError::NothingOnIt);
    }
    let pivot = sum.map(|s| s / count);
    let shift = match &walk.moved {
        Some(m) => shift_of(m, &labels, plane.normal, pivot, &point)?,
        None => [0.0; 3],
    };
    let moving = |at: usize| {
        walk.moved
            .as_ref()
            .is_some_and(|m| m.readings.get(at) == Some(&true))
    };
    // The camera turns by `yaw` about the normal through the pivot: the
    // points, seen from it, by the opposite turn.
    let turn = rotation(plane.normal, -yaw_deg.to_radians());
    let camera = scaled(intrinsics, scale)?;
    let (w, h) = (
        (f64::from(w) * scale).round().max(1.0) as u32,
        (f64::from(h) * scale).round().max(1.0) as u32,
    );
    let mut view = Reprojection {
        intrinsics: camera,
        colour: RgbImage::from_pixel(w, h, Rgb([0, 0, 0])),
        depth: DepthPixels::new(w, h),
        source: vec![None; (w * h) as usize],
    };
    let mut nearest = vec![f64::INFINITY; (w * h) as usize];
    let (fw, fh) = colour.dimensions();
    for v in 0..fh {
        for u in 0..fw {
            let Some(mut p) = point(u, v) else { continue };
            if moving((v * fw + u) as usize) {
                (0..3).for_each(|k| p[k] += shift[k]);
            }
            let q = moved(&turn, pivot, p);
            let Some([x, y]) = camera.project(q) else {
                continue;
            };
            // Each reading covers the 2 x 2 pixels around where it lands,
            // so that a surface seen closer keeps no cracks.
            for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
                let (tx, ty) = ((x + dx - 0.5).floor(), (y + dy - 0.5).floor());
                if tx < 0.0 || ty < 0.0 || tx >= f64::from(w) || ty >= f64::from(h) {
                    continue;
                }
                let at = ty as usize * w as usize + tx as usize;
                if q[2] < nearest[at] {
                    nearest[at] = q[2];
                    view.source[at] = Some(v * fw + u);
                    let (tx, ty) = (tx as u32, ty as u32);
                    view.colour.put_pixel(tx, ty, *colour.get_pixel(u, v));
                    let units = (q[2] / metres).round().min(f64::from(u16::MAX)) as u16;
                    view.depth.put_pixel(tx, ty, Luma([units]));
                }
            }
        }
    }
    Ok(view)
}

/// How far `m`'s readings move: `m.metres` along the plane (normal
/// `normal`), away from `pivot`; refused where they would land within
/// [`FREE`] of a reading of another object (`labels` > 0).
fn shift_of(
    m: &Moved<'_>,
    labels: &LabelImage,
    normal: [f64; 3],
    pivot: [f64; 3],
    point: &impl Fn(u32, u32) -> Option<[f64; 3]>,
) -> Result<[f64; 3], ReprojectError> {
    let (mine, others) = readings_of(m, labels, point);
    if mine.is_empty() {
        return Err(ReprojectError::NothingToMove);
    }
    let shift = direction_out(&mine, normal, pivot).map(|x| x * m.metres);
    if lands_free(&mine, &others, shift, normal) {
        Ok(shift)
    } else {
        Err(ReprojectError::NotFree(FREE))
    }
}

/// The points of `m`'s readings, and of the other objects' (the
/// segments of `labels` not mostly made of `m`'s readings: a segment of
/// the object has outline pixels its readings lack).
fn readings_of(
    m: &Moved<'_>,
    labels: &LabelImage,
    point: &impl Fn(u32, u32) -> Option<[f64; 3]>,
) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let w = labels.width();
    let is_mine = |u: u32, v: u32| m.readings.get((v * w + u) as usize) == Some(&true);
    let mut share = std::collections::HashMap::<u16, (usize, usize)>::new();
    for (u, v, l) in labels.enumerate_pixels() {
        let e = share.entry(l.0[0]).or_default();
        e.0 += usize::from(is_mine(u, v));
        e.1 += 1;
    }
    let its = |l: u16| share.get(&l).is_some_and(|&(a, b)| 2 * a >= b);
    let (mut mine, mut others) = (Vec::new(), Vec::new());
    for (u, v, l) in labels.enumerate_pixels() {
        let Some(p) = point(u, v) else { continue };
        if is_mine(u, v) {
            mine.push(p);
        } else if l.0[0] > 0 && !its(l.0[0]) {
            others.push(p);
        }
    }
    (mine, others)
}

/// The unit direction along the plane (normal `normal`) from `pivot` to
/// the centre of `points`; any direction along it where they are centred
/// on it.
fn direction_out(points: &[[f64; 3]], normal: [f64; 3], pivot: [f64; 3]) -> [f64; 3] {
    let k = points.len().max(1) as f64;
    let sum = points
        .iter()
        .fold([0.0; 3], |c, p| std::array::from_fn(|i| c[i] + p[i]));
    let d: [f64; 3] = std::array::from_fn(|i| sum[i] / k - pivot[i]);
    let h = dot(d, normal);
    let out: [f64; 3] = std::array::from_fn(|i| d[i] - h * normal[i]);
    let length = dot(out, out).sqrt();
    if length > 1e-6 {
        out.map(|x| x / length)
    } else {
        plane_basis(normal)[0]
    }
}

/// Whether `mine` moved by `shift` lands with no point of `others`
/// within [`FREE`] along the plane (normal `normal`): the cells of a grid
/// of `FREE / 2` the others occupy against every cell within two of a
/// moved point (so some places a little farther are refused too).
fn lands_free(mine: &[[f64; 3]], others: &[[f64; 3]], shift: [f64; 3], normal: [f64; 3]) -> bool {
    let cell = FREE / 2.0;
    let basis = plane_basis(normal);
    let key = |p: [f64; 3]| {
        let c = basis.map(|b| (dot(p, b) / cell).floor() as i64);
        (c[0], c[1])
    };
    let occupied: std::collections::HashSet<(i64, i64)> = others.iter().map(|&p| key(p)).collect();
    mine.iter().all(|p| {
        let (x, y) = key(std::array::from_fn(|i| p[i] + shift[i]));
        (-2..=2).all(|dx| (-2..=2).all(|dy| !occupied.contains(&(x + dx, y + dy))))
    })
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Two unit vectors that span the plane of unit normal `n`.
fn plane_basis(n: [f64; 3]) -> [[f64; 3]; 2] {
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let unit = |a: [f64; 3]| {
        let l = a.iter().map(|x| x * x).sum::<f64>().sqrt();
        a.map(|x| x / l)
    };
    let seed = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = unit(cross(n, seed));
    [e1, cross(n, e1)]
}

/// `intrinsics` of an image `scale` times as large in each direction
/// (pixel centres at integers, so the principal point keeps its place on
/// the image).
fn scaled(intrinsics: Intrinsics, scale: f64) -> Result<Intrinsics, ReprojectError> {
    if scale == 1.0 {
        return Ok(intrinsics);
    }
    let centre = |c: f64| (c + 0.5) * scale - 0.5;
    Intrinsics::new(
        intrinsics.fx() * scale,
        intrinsics.fy() * scale,
        centre(intrinsics.cx()).max(0.0),
        centre(intrinsics.cy()).max(0.0),
    )
    .map_err(|_| ReprojectError::Scale(scale))
}

/// What a second camera adds to a view of the first one's readings: its
/// own depth noise and colour response. Applied by [`SecondSensor::apply`],
/// deterministically for a seed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SecondSensor {
    /// `c` of its own per-reading depth noise, `sigma = c z^2` (metres, `z`
    /// in metres), independent of the first camera's.
    pub depth_c: f64,
    /// Largest error of each colour channel's gain (white balance), as a
    /// share: each gain is drawn uniformly within 1 +- this.
    pub white_balance: f64,
    /// Largest error of the exposure (all channels' common gain), as a share.
    pub exposure: f64,
    /// Each pixel's colour noise, in levels of 255 (one sigma).
    pub colour_sigma: f64,
    pub seed: u64,
}

impl SecondSensor {
    /// Puts this sensor's noise and colour response on `view`, whose depth
    /// is in units of `metres_per_unit`. Holes stay holes; a reading the
    /// noise would take to zero or below keeps one unit.
    pub fn apply(&self, view: &mut Reprojection, metres_per_unit: f64) {
        let mut rng = Gaussian::new(self.seed);
        let exposure = 1.0 + self.exposure * rng.uniform_signed();
        let gains: [f64; 3] =
            std::array::from_fn(|_| exposure * (1.0 + self.white_balance * rng.uniform_signed()));
        for p in view.colour.pixels_mut() {
            for (c, g) in p.0.iter_mut().zip(gains) {
                let level = f64::from(*c) * g + self.colour_sigma * rng.normal();
                *c = level.round().clamp(0.0, 255.0) as u8;
            }
        }
        for d in view.depth.pixels_mut() {
            if d.0[0] == 0 {
                continue;
            }
            let z = f64::from(d.0[0]) * metres_per_unit;
            let noisy = z + self.depth_c * z * z * rng.normal();
            d.0[0] = (noisy / metres_per_unit)
                .round()
                .clamp(1.0, f64::from(u16::MAX)) as u16;
        }
    }
}

/// Standard normal draws (Box-Muller over SplitMix64): reproducible for a
/// seed on every machine.
struct Gaussian {
    state: u64,
    spare: Option<f64>,
}

impl Gaussian {
    fn new(seed: u64) -> Self {
        Self {
            state: seed,
            spare: None,
        }
    }

    /// Uniform in [0, 1).
    fn uniform(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [-1, 1).
    fn uniform_signed(&mut self) -> f64 {
        2.0 * self.uniform() - 1.0
    }

    fn normal(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        let r = (-2.0 * (1.0 - self.uniform()).ln()).sqrt();
        let (s, c) = (std::f64::consts::TAU * self.uniform()).sin_cos();
        self.spare = Some(r * s);
        r * c
    }
}

/// The value most pixels of `label` in `labels` map to through `of`
/// (given each pixel's row-major index), if it is not 0 and at least
/// `share` of them map to it.
pub fn majority(
    labels: &LabelImage,
    label: u16,
    share: f64,
    of: impl Fn(usize) -> u16,
) -> Option<u16> {
    let mut votes = std::collections::BTreeMap::<u16, usize>::new();
    let mut pixels = 0usize;
    for (at, l) in labels.as_raw().iter().enumerate() {
        if *l == label {
            pixels += 1;
            *votes.entry(of(at)).or_default() += 1;
        }
    }
    let (&best, &n) = votes
        .iter()
        .max_by_key(|(l, n)| (**n, std::cmp::Reverse(**l)))?;
    (best != 0 && n as f64 >= share * pixels as f64).then_some(best)
}

/// The rotation by `angle` about the unit `axis` (Rodrigues).
fn rotation(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let [x, y, z] = axis;
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]
}

fn moved(r: &[[f64; 3]; 3], pivot: [f64; 3], p: [f64; 3]) -> [f64; 3] {
    let d = [p[0] - pivot[0], p[1] - pivot[1], p[2] - pivot[2]];
    std::array::from_fn(|k| r[k][0] * d[0] + r[k][1] * d[1] + r[k][2] * d[2] + pivot[k])
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::{majority, rotation};
    use crate::LabelImage;

    /// A quarter turn about z takes x to y; the inverse turn undoes it.
    #[test]
    fn rotations_turn_about_their_axis() {
        let r = rotation([0.0, 0.0, 1.0], std::f64::consts::FRAC_PI_2);
        let x = [1.0, 0.0, 0.0];
        let y: Vec<f64> = (0..3)
            .map(|k| (0..3).map(|j| r[k][j] * x[j]).sum())
            .collect();
        assert!((y[0]).abs() < 1e-12 && (y[1] - 1.0).abs() < 1e-12 && y[2].abs() < 1e-12);
    }

    /// The majority needs its share and is never 0.
    #[test]
    fn the_majority_needs_its_share() {
        let labels = LabelImage::from_raw(4, 1, vec![5, 5, 5, 0]).unwrap();
        let through = [7u16, 7, 8, 9];
        assert_eq!(majority(&labels, 5, 0.5, |at| through[at]), Some(7));
        assert_eq!(majority(&labels, 5, 0.7, |at| through[at]), None);
        assert_eq!(majority(&labels, 5, 0.5, |_| 0), None);
        assert_eq!(majority(&labels, 3, 0.5, |at| through[at]), None);
    }
}
