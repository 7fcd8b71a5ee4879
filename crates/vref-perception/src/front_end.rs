//! Masks to objects: where each object is, how sure that is, what it
//! looks like.
//!
//! Position: the depth readings of the mask's interior (the mask eroded
//! by one pixel, where a reading may mix object and background), their
//! median, then only the readings within the object's own size of it (a
//! surface cannot span more depth than the object is large; what lies
//! further is background seen through holes or flying pixels), and the
//! median of those. The object is seen through the mean pixel of those
//! readings, and its centre lies behind the visible surface: the point is
//! pushed back along that ray by `centre_offset` times the radius of a
//! disc of the mask's area at that depth.

use crate::features::{BoundingBox, FEATURE_DIM, Patch, describe};
use crate::{Frame, FrameError, FrontEndSettings, Mask};

/// One measured object.
#[derive(Debug, Clone, PartialEq)]
pub struct Detection {
    /// The mask's id.
    pub id: u64,
    /// Camera frame, metres (x right, y down, z forward).
    pub position: [f64; 3],
    /// Per-axis standard deviation of `position`, metres (the wire's
    /// `position_sigma`: together the depth error along the ray).
    pub sigma: [f64; 3],
    pub feature: [f32; FEATURE_DIM],
    /// Depth readings the position rests on.
    pub depth_pixels: u32,
    /// The mask's box in the image.
    pub bbox: BoundingBox,
}

/// Masks of a frame that gave no object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Skipped {
    /// Fewer mask pixels than the minimum.
    pub too_small: u32,
    /// Enough mask pixels, but fewer depth readings among them than the
    /// minimum.
    pub no_depth: u32,
    /// Masks covering every pixel of the frame: a segmenter's background
    /// or an inverted mask, not an object.
    pub whole_frame: u32,
}

/// One depth reading of a mask.
#[derive(Debug, Clone, Copy)]
struct Sample {
    depth: u16,
    u: u16,
    v: u16,
    interior: bool,
}

/// The front end of one camera. Its buffers grow to the largest mask seen
/// and are reused for every frame after.
#[derive(Debug)]
pub struct FrontEnd {
    settings: FrontEndSettings,
    samples: Vec<Sample>,
    depths: Vec<u16>,
}

enum Outcome {
    Detected,
    TooSmall,
    NoDepth,
    WholeFrame,
}

impl FrontEnd {
    pub fn new(settings: FrontEndSettings) -> Self {
        Self {
            settings,
            samples: Vec::new(),
            depths: Vec::new(),
        }
    }

    pub fn settings(&self) -> &FrontEndSettings {
        &self.settings
    }

    /// The objects of `frame` into `out` (cleared first), in mask order;
    /// masks that give none are counted. Refuses frames whose parts do
    /// not fit together.
    pub fn process(
        &mut self,
        frame: &Frame<'_>,
        out: &mut Vec<Detection>,
    ) -> Result<Skipped, FrameError> {
        frame.check()?;
        out.clear();
        let mut skipped = Skipped::default();
        for mask in frame.masks {
            match self.measure(frame, mask, out) {
                Outcome::Detected => {}
                Outcome::TooSmall => skipped.too_small += 1,
                Outcome::NoDepth => skipped.no_depth += 1,
                Outcome::WholeFrame => skipped.whole_frame += 1,
            }
        }
        Ok(skipped)
    }

    /// The capacities of the reused buffers, for tests of reuse.
    pub fn buffer_capacity(&self) -> usize {
        self.samples.capacity() + self.depths.capacity()
    }

    /// Measures `mask`'s object into `out`, or says why not.
    fn measure(&mut self, frame: &Frame<'_>, mask: &Mask<'_>, out: &mut Vec<Detection>) -> Outcome {
        let (width, height) = frame.colour.dimensions();
        let m = mask.pixels.as_raw();
        let Some((bbox, area)) = bounding_box(m, width as usize, height as usize) else {
            return Outcome::TooSmall;
        };
        if area < self.settings.min_pixels {
            return Outcome::TooSmall;
        }
        if area == m.len() {
            return Outcome::WholeFrame;
        }
        self.collect(frame, m, bbox);
        if self.samples.len() < self.settings.min_pixels {
            return Outcome::NoDepth;
        }
        let interior = self.samples.iter().filter(|s| s.interior).count();
        // Thin masks are mostly outline: their interior is no better
        // than the rest, and too small a share to rest on.
        if 2 * interior >= self.samples.len() {
            self.samples.retain(|s| s.interior);
        }
        let Some((depth, u, v, n)) = self.robust_depth(frame, bbox) else {
            return Outcome::NoDepth;
        };
        let intr = &frame.intrinsics;
        let focal = 0.5 * (intr.fx() + intr.fy());
        let surface = f64::from(depth) * frame.depth.metres_per_unit();
        let radius = (area as f64 / std::f64::consts::PI).sqrt() * surface / focal;
        let z = surface + self.settings.centre_offset * radius;
        let position = intr.back_project(u, v, z);
        let sigma = self.settings.noise.position_sigma(position, n);
        let mut feature = [0.0; FEATURE_DIM];
        let patch = Patch {
            rgb: frame.colour.as_raw(),
            mask: m,
            width: width as usize,
            bbox,
        };
        describe(&patch, area, &mut feature);
        out.push(Detection {
            id: mask.id,
            position,
            sigma,
            feature,
            depth_pixels: u32::try_from(n).unwrap_or(u32::MAX),
            bbox,
        });
        Outcome::Detected
    }

    /// The depth readings of the mask into `samples`, each marked interior
    /// when its four neighbours are in the mask too.
    fn collect(&mut self, frame: &Frame<'_>, m: &[u8], bbox: BoundingBox) {
        let (width, height) = frame.colour.dimensions();
        let (w, h) = (width as usize, height as usize);
        let depth = frame.depth.pixels().as_raw();
        self.samples.clear();
        for v in bbox.v0 as usize..bbox.v1 as usize {
            for u in bbox.u0 as usize..bbox.u1 as usize {
                let i = v * w + u;
                if m[i] == 0 || depth[i] == 0 {
                    continue;
                }
                let interior = u > 0
                    && u + 1 < w
                    && v > 0
                    && v + 1 < h
                    && m[i - 1] != 0
                    && m[i + 1] != 0
                    && m[i - w] != 0
                    && m[i + w] != 0;
                // Images wider or taller than 65535 pixels are not cameras'.
                self.samples.push(Sample {
                    depth: depth[i],
                    u: u as u16,
                    v: v as u16,
                    interior,
                });
            }
        }
    }

    /// Median depth (in the image's units) of the samples within the
    /// object's size of their first median, their mean pixel and count.
    fn robust_depth(
        &mut self,
        frame: &Frame<'_>,
        bbox: BoundingBox,
    ) -> Option<(u16, f64, f64, usize)> {
        let first = median(&mut self.depths, self.samples.iter().map(|s| s.depth))?;
        let intr = &frame.intrinsics;
        let mpu = frame.depth.metres_per_unit();
        let z = f64::from(first) * mpu;
        let extent = f64::from(bbox.width()) * z / intr.fx();
        let extent = extent.hypot(f64::from(bbox.height()) * z / intr.fy());
        let band = extent.max(3.0 * self.settings.noise.pixel.at(z)) / mpu;
        let keep = |s: &Sample| (f64::from(s.depth) - f64::from(first)).abs() <= band;
        let (mut su, mut sv, mut n) = (0u64, 0u64, 0usize);
        for s in self.samples.iter().filter(|s| keep(s)) {
            su += u64::from(s.u);
            sv += u64::from(s.v);
            n += 1;
        }
        let depth = median(
            &mut self.depths,
            self.samples.iter().filter(|s| keep(s)).map(|s| s.depth),
        )?;
        let n_f = n as f64;
        Some((depth, su as f64 / n_f, sv as f64 / n_f, n))
    }
}

/// The median of `values`, using `buffer` as scratch; `None` when empty.
fn median(buffer: &mut Vec<u16>, values: impl Iterator<Item = u16>) -> Option<u16> {
    buffer.clear();
    buffer.extend(values);
    if buffer.is_empty() {
        return None;
    }
    let mid = buffer.len() / 2;
    Some(*buffer.select_nth_unstable(mid).1)
}

/// Whether a row of a mask is all zero: most rows of a mask are, so this
/// is one pass that ORs 64 bytes at a time (which vectorises) instead of
/// a test per byte.
fn is_empty(row: &[u8]) -> bool {
    let mut chunks = row.chunks_exact(64);
    for chunk in &mut chunks {
        if chunk.iter().fold(0u8, |a, &b| a | b) != 0 {
            return false;
        }
    }
    chunks.remainder().iter().all(|&b| b == 0)
}

/// The box of a mask's non-zero pixels and their count; `None` when
/// there are none.
fn bounding_box(m: &[u8], width: usize, height: usize) -> Option<(BoundingBox, usize)> {
    let (mut u0, mut u1, mut v0, mut v1) = (usize::MAX, 0, usize::MAX, 0);
    let mut area = 0;
    for v in 0..height {
        let row = &m[v * width..(v + 1) * width];
        if is_empty(row) {
            continue;
        }
        let first = row.iter().position(|&b| b != 0).unwrap_or(0);
        let last = row.iter().rposition(|&b| b != 0).unwrap_or(0);
        area += row[first..=last].iter().filter(|&&b| b != 0).count();
        u0 = u0.min(first);
        u1 = u1.max(last + 1);
        v0 = v0.min(v);
        v1 = v + 1;
    }
    if area == 0 {
        return None;
    }
    let to = |x: usize| u32::try_from(x).unwrap_or(u32::MAX);
    Some((
        BoundingBox {
            u0: to(u0),
            v0: to(v0),
            u1: to(u1),
            v1: to(v1),
        },
        area,
    ))
}
