//! The appearance feature of one masked object, in the paper's spirit: a
//! colour histogram and a histogram of oriented gradients over the mask's
//! box, each block L2-normalised, neither depending on the mask's size.
//!
//! - Colour (28): hue in 12 circular bins times 2 brightness levels for
//!   coloured pixels, 4 brightness bins for grey ones. Hue, not raw RGB:
//!   a camera's white balance scales the three channels by a few per cent,
//!   which moves a saturated colour's hue by a few degrees only. A pixel
//!   counts as grey below saturation 0.15 (what a white balance of 8 %
//!   alone gives a grey surface) and fully as coloured above 0.35, blended
//!   between. Soft (linear) binning, so that a small shift of hue or
//!   brightness moves weight smoothly between neighbouring bins.
//! - Shape (36): the mask's box resampled to a 16 x 16 grid by area
//!   averaging (pixels outside the mask take the mask's mean grey, so the
//!   background never enters but the outline does), gradient orientations
//!   in 9 unsigned bins over 2 x 2 cells, weighted by gradient magnitude.

/// Length of the feature (the wire carries at most 64).
pub const FEATURE_DIM: usize = COLOUR_DIM + SHAPE_DIM;
pub const COLOUR_DIM: usize = HUE_BINS * VALUE_LEVELS + GREY_BINS;
pub const SHAPE_DIM: usize = CELLS * CELLS * ORIENTATIONS;

const HUE_BINS: usize = 12;
const VALUE_LEVELS: usize = 2;
const GREY_BINS: usize = 4;
const GRID: usize = 16;
const CELLS: usize = 2;
const ORIENTATIONS: usize = 9;
/// Saturation from which a pixel starts to count as coloured, and from
/// which it counts fully.
const GREY_SATURATION: [f32; 2] = [0.15, 0.35];
/// Brightness below which hue means nothing (sensor noise dominates).
const DARK_VALUE: [f32; 2] = [0.04, 0.12];
/// Pixels of a mask the colour histogram needs at most: a large mask is
/// sampled on a regular grid, which keeps the histogram's shape (a
/// histogram of a thousand samples is as good as one of all of them) and
/// bounds the work per object.
const COLOUR_SAMPLES: usize = 1024;

/// A mask's bounding box, pixels, inclusive of its first and exclusive of
/// its last row and column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BoundingBox {
    pub u0: u32,
    pub v0: u32,
    pub u1: u32,
    pub v1: u32,
}

impl BoundingBox {
    pub fn width(&self) -> u32 {
        self.u1 - self.u0
    }

    pub fn height(&self) -> u32 {
        self.v1 - self.v0
    }
}

/// The image of one object: its pixels in the colour image and the mask.
pub(crate) struct Patch<'a> {
    pub rgb: &'a [u8],
    pub mask: &'a [u8],
    pub width: usize,
    pub bbox: BoundingBox,
}

/// The feature of `patch`, whose mask has `area` pixels, into `out`.
pub(crate) fn describe(patch: &Patch<'_>, area: usize, out: &mut [f32; FEATURE_DIM]) {
    out.fill(0.0);
    let (colour, shape) = out.split_at_mut(COLOUR_DIM);
    let stride = ((area as f64 / COLOUR_SAMPLES as f64).sqrt().ceil() as usize).max(1);
    let mean_grey = colour_histogram(patch, stride, colour);
    gradient_histogram(patch, mean_grey, shape);
    normalise(colour);
    normalise(shape);
}

fn normalise(block: &mut [f32]) {
    let norm = block.iter().map(|v| v * v).sum::<f32>().sqrt();
    if norm > 0.0 {
        block.iter_mut().for_each(|v| *v /= norm);
    }
}

/// Linear ramp from 0 at `edges[0]` to 1 at `edges[1]`.
fn ramp(x: f32, edges: [f32; 2]) -> f32 {
    ((x - edges[0]) / (edges[1] - edges[0])).clamp(0.0, 1.0)
}

/// Adds `weight` at fractional position `x` (bin centres at 0, 1, ...)
/// of `bins` bins of stride `stride` from `base`, split between the two
/// nearest; circular or clamped at the ends.
fn soft_add(
    hist: &mut [f32],
    base: usize,
    stride: usize,
    bins: usize,
    x: f32,
    circular: bool,
    weight: f32,
) {
    let (lo, frac) = if circular {
        let x = x.rem_euclid(bins as f32);
        (x.floor(), x - x.floor())
    } else {
        let x = x.clamp(0.0, (bins - 1) as f32);
        (x.floor().min((bins - 1) as f32), x - x.floor())
    };
    let lo = lo as usize % bins;
    let hi = if circular {
        (lo + 1) % bins
    } else {
        (lo + 1).min(bins - 1)
    };
    hist[base + lo * stride] += weight * (1.0 - frac);
    hist[base + hi * stride] += weight * frac;
}

/// Hue (in sextants, [0, 6)), saturation and value of an RGB pixel.
fn hsv(r: f32, g: f32, b: f32) -> (f32, f32, f32) {
    let max = r.max(g).max(b);
    let min = r.min(g).min(b);
    let chroma = max - min;
    if max <= 0.0 || chroma <= 0.0 {
        return (0.0, 0.0, max);
    }
    let hue = if max == r {
        ((g - b) / chroma).rem_euclid(6.0)
    } else if max == g {
        (b - r) / chroma + 2.0
    } else {
        (r - g) / chroma + 4.0
    };
    (hue, chroma / max, max)
}

/// The colour block (unnormalised) from the mask's pixels on a grid of
/// stride `stride`; returns the mask's mean grey.
fn colour_histogram(patch: &Patch<'_>, stride: usize, hist: &mut [f32]) -> f32 {
    let bbox = patch.bbox;
    let (mut grey_sum, mut count) = (0.0f32, 0u32);
    for v in (bbox.v0 as usize..bbox.v1 as usize).step_by(stride) {
        let row = v * patch.width;
        for u in (bbox.u0 as usize..bbox.u1 as usize).step_by(stride) {
            let i = row + u;
            if patch.mask[i] == 0 {
                continue;
            }
            let px = &patch.rgb[3 * i..3 * i + 3];
            let (r, g, b) = (
                f32::from(px[0]) / 255.0,
                f32::from(px[1]) / 255.0,
                f32::from(px[2]) / 255.0,
            );
            let (hue, saturation, value) = hsv(r, g, b);
            grey_sum += (r + g + b) / 3.0;
            count += 1;
            let coloured = ramp(saturation, GREY_SATURATION) * ramp(value, DARK_VALUE);
            if coloured > 0.0 {
                // Hue x value: weight the two value levels per hue bin.
                let x_hue = hue * HUE_BINS as f32 / 6.0 - 0.5;
                let x_value = value * VALUE_LEVELS as f32 - 0.5;
                let x = x_value.clamp(0.0, (VALUE_LEVELS - 1) as f32);
                let level = (x.floor() as usize).min(VALUE_LEVELS - 1);
                let frac = x - level as f32;
                let next = (level + 1).min(VALUE_LEVELS - 1);
                for (lv, w) in [(level, 1.0 - frac), (next, frac)] {
                    if w > 0.0 {
                        soft_add(hist, lv, VALUE_LEVELS, HUE_BINS, x_hue, true, coloured * w);
                    }
                }
            }
            if coloured < 1.0 {
                let base = HUE_BINS * VALUE_LEVELS;
                let x = value * GREY_BINS as f32 - 0.5;
                soft_add(hist, base, 1, GREY_BINS, x, false, 1.0 - coloured);
            }
        }
    }
    if count == 0 {
        0.0
    } else {
        grey_sum / count as f32
    }
}

/// The shape block (unnormalised) of the patch resampled to the grid.
fn gradient_histogram(patch: &Patch<'_>, mean_grey: f32, hist: &mut [f32]) {
    let grid = resample(patch, mean_grey);
    let at = |x: usize, y: usize| grid[y * GRID + x];
    for y in 0..GRID {
        for x in 0..GRID {
            let dx = at((x + 1).min(GRID - 1), y) - at(x.saturating_sub(1), y);
            let dy = at(x, (y + 1).min(GRID - 1)) - at(x, y.saturating_sub(1));
            let magnitude = dx.hypot(dy);
            if magnitude <= 0.0 {
                continue;
            }
            // Unsigned orientation: an edge is the same edge whichever
            // side is brighter (object against a brighter or darker table).
            let angle = dy.atan2(dx).rem_euclid(std::f32::consts::PI);
            let bin = angle / std::f32::consts::PI * ORIENTATIONS as f32 - 0.5;
            let cell = (y * CELLS / GRID) * CELLS + x * CELLS / GRID;
            soft_add(
                hist,
                cell * ORIENTATIONS,
                1,
                ORIENTATIONS,
                bin,
                true,
                magnitude,
            );
        }
    }
}

/// The patch's grey values on a GRID x GRID grid over its box: the mean
/// of the pixels each grid cell covers (every pixel of the box belongs to
/// exactly one cell; in boxes over twice the grid, every `stride`-th
/// pixel, at least two per cell and direction), or the pixel at the
/// cell's centre where the box is smaller than the grid.
fn resample(patch: &Patch<'_>, mean_grey: f32) -> [f32; GRID * GRID] {
    let bbox = patch.bbox;
    let (w, h) = (bbox.width() as usize, bbox.height() as usize);
    let grey = |u: usize, v: usize| -> f32 {
        let i = (bbox.v0 as usize + v) * patch.width + bbox.u0 as usize + u;
        if patch.mask[i] == 0 {
            return mean_grey;
        }
        let px = &patch.rgb[3 * i..3 * i + 3];
        (f32::from(px[0]) + f32::from(px[1]) + f32::from(px[2])) / (3.0 * 255.0)
    };
    let mut sum = [0.0f32; GRID * GRID];
    let mut count = [0u32; GRID * GRID];
    let stride = (w.min(h) / (2 * GRID)).max(1);
    for v in (0..h).step_by(stride) {
        let gy = v * GRID / h;
        for u in (0..w).step_by(stride) {
            let cell = gy * GRID + u * GRID / w;
            sum[cell] += grey(u, v);
            count[cell] += 1;
        }
    }
    for gy in 0..GRID {
        for gx in 0..GRID {
            let cell = gy * GRID + gx;
            sum[cell] = if count[cell] == 0 {
                grey((2 * gx + 1) * w / (2 * GRID), (2 * gy + 1) * h / (2 * GRID))
            } else {
                sum[cell] / count[cell] as f32
            };
        }
    }
    sum
}
