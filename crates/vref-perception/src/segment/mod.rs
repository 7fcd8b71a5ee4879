//! The class-agnostic segmenter: colour, depth and intrinsics in, an
//! instance label image out (one `u16` per pixel, 0 = background).
//!
//! The classical tabletop method: the supporting plane (RANSAC on a
//! sparse grid, least-squares refit), then what stands on it, split where
//! depth jumps (relative to depth) and where two surfaces meet in a
//! concave crease (normals of box-filtered depth), with colour edges
//! deciding where the geometry is unsure; connected segments grown back
//! over the cuts and down to the objects' feet, small ones dropped.
//! Readings of 0 (none) are never an object's, and a flying pixel at an
//! outline stays with neither side of the jump it sits on unless the
//! growth reaches it through continuous depth.
//!
//! A frame without a supporting plane (a wall, a hand over the lens, no
//! depth) gives zero objects and a [`NoSupport`] reason, never a made-up
//! plane. The segmenter keeps its buffers: frames after the first of a
//! size allocate nothing.

mod components;
mod enclosed;
mod masks;
mod merge;
mod normals;
mod overlay;
mod plane;
pub mod score;
mod settings;
mod split;
mod warp;

use image::{ImageBuffer, Luma, RgbImage};

pub use masks::{LabelMask, label_masks};
pub use overlay::overlay;
pub use plane::Plane;
pub use settings::SegmentationSettings;

use crate::{DepthImage, Intrinsics};

/// One `u16` label per pixel: 0 background, 1..=n the objects.
pub type LabelImage = ImageBuffer<Luma<u16>, Vec<u16>>;

/// Fewer sampled readings than this cannot show a plane.
const MIN_PLANE_SAMPLES: usize = 50;

/// Half width of the box whose mean height the seed test reads.
const SEED_RADIUS: usize = 1;

/// What the segmenter reads.
#[derive(Debug, Clone, Copy)]
pub struct RgbdFrame<'a> {
    pub colour: &'a RgbImage,
    /// Registered to `colour`: the same pixel sees the same point.
    pub depth: &'a DepthImage,
    pub intrinsics: Intrinsics,
    /// Gravity's up direction in the camera frame, where known (a robot
    /// knows its camera's mounting): the plane must then face it.
    pub up: Option<[f64; 3]>,
}

/// Why a frame cannot be segmented at all.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SegmentError {
    #[error("the depth image is {found_width}x{found_height}, the colour image {width}x{height}")]
    DepthSize {
        width: u32,
        height: u32,
        found_width: u32,
        found_height: u32,
    },
    #[error("the colour image is empty (0 pixels)")]
    Empty,
    #[error("the image is {width}x{height}, more pixels than a label image can index")]
    TooLarge { width: u32, height: u32 },
    #[error("the up vector {up:?} is no direction (it must be finite and not zero)")]
    BadUp { up: [f64; 3] },
}

/// Why a frame has no supporting plane (and so no objects).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NoSupport {
    /// Too few depth readings to fit a plane to (a covered lens, a camera
    /// too close or too far).
    NoReadings { samples: usize, needed: usize },
    /// No plane holds enough of the readings (a hand over the lens, a
    /// cluttered close-up).
    NoPlane { share: f64, needed: f64 },
    /// The largest plane faces the camera (a wall, a box side seen face
    /// on): tilted less than `min_plane_tilt_deg` against the image plane.
    FacesCamera { tilt_deg: f64, min_deg: f64 },
    /// The largest plane is not level: its normal is this far from the
    /// given up vector.
    NotLevel { angle_deg: f64, max_deg: f64 },
}

impl std::fmt::Display for NoSupport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            NoSupport::NoReadings { samples, needed } => write!(
                f,
                "no supporting plane: {samples} sampled depth readings, at least {needed} needed"
            ),
            NoSupport::NoPlane { share, needed } => write!(
                f,
                "no supporting plane: the best plane holds {:.0} % of the readings, at least {:.0} % needed",
                100.0 * share,
                100.0 * needed
            ),
            NoSupport::FacesCamera { tilt_deg, min_deg } => write!(
                f,
                "no supporting plane: the largest plane faces the camera (tilted {tilt_deg:.1} deg, at least {min_deg:.1} needed), a wall rather than a table"
            ),
            NoSupport::NotLevel { angle_deg, max_deg } => write!(
                f,
                "no supporting plane: the largest plane is {angle_deg:.1} deg off level (at most {max_deg:.1})"
            ),
        }
    }
}

/// What one frame gave.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Segmentation {
    /// Labels `1..=objects` are in the image.
    Objects { objects: usize, plane: Plane },
    /// Every label is 0.
    NoSupport(NoSupport),
}

impl Segmentation {
    pub fn objects(&self) -> usize {
        match self {
            Segmentation::Objects { objects, .. } => *objects,
            Segmentation::NoSupport(_) => 0,
        }
    }
}

/// The segmenter and its per-pixel buffers, reused frame after frame.
#[derive(Debug)]
pub struct Segmenter {
    settings: SegmentationSettings,
    /// Depth in metres, 0 where there is no reading.
    z: Vec<f32>,
    smooth: Vec<f32>,
    /// Height above the plane (0 where no reading), and its box mean over
    /// the read pixels, which the seed test reads.
    height: Vec<f32>,
    height_mean: Vec<f32>,
    read: Vec<bool>,
    normals: Vec<[f32; 3]>,
    /// Above the plane by the seed height; cleared where cut.
    seed: Vec<bool>,
    /// Above the plane by the growth height.
    grow: Vec<bool>,
    cut: Vec<bool>,
    xu: Vec<f32>,
    yv: Vec<f32>,
    samples: Vec<plane::Sample>,
    boxes: normals::BoxScratch,
    components: components::Scratch,
}

impl Segmenter {
    /// `settings` should have passed [`SegmentationSettings::validate`];
    /// unvalidated values make poor labels, never a panic.
    pub fn new(settings: SegmentationSettings) -> Self {
        Self {
            settings,
            z: Vec::new(),
            smooth: Vec::new(),
            height: Vec::new(),
            height_mean: Vec::new(),
            read: Vec::new(),
            normals: Vec::new(),
            seed: Vec::new(),
            grow: Vec::new(),
            cut: Vec::new(),
            xu: Vec::new(),
            yv: Vec::new(),
            samples: Vec::new(),
            boxes: normals::BoxScratch::default(),
            components: components::Scratch::default(),
        }
    }

    pub fn settings(&self) -> &SegmentationSettings {
        &self.settings
    }

    /// Bytes of reusable buffers held (they only grow).
    pub fn buffer_capacity(&self) -> usize {
        self.z.capacity() * 4
            + self.smooth.capacity() * 4
            + self.height.capacity() * 4
            + self.height_mean.capacity() * 4
            + self.read.capacity()
            + self.normals.capacity() * 12
            + self.seed.capacity()
            + self.grow.capacity()
            + self.cut.capacity()
            + self.samples.capacity()
            + self.boxes.capacity()
            + self.components.capacity()
    }

    /// Segments `frame` into `labels` (resized to the frame if needed).
    pub fn segment(
        &mut self,
        frame: &RgbdFrame<'_>,
        labels: &mut LabelImage,
    ) -> Result<Segmentation, SegmentError> {
        let (width, height) = frame.colour.dimensions();
        if width == 0 || height == 0 {
            return Err(SegmentError::Empty);
        }
        let (dw, dh) = frame.depth.pixels().dimensions();
        if (dw, dh) != (width, height) {
            return Err(SegmentError::DepthSize {
                width,
                height,
                found_width: dw,
                found_height: dh,
            });
        }
        let pixels = u64::from(width) * u64::from(height);
        if pixels >= u64::from(u32::MAX) {
            return Err(SegmentError::TooLarge { width, height });
        }
        if let Some(up) = frame.up {
            let length = up.iter().map(|c| c * c).sum::<f64>().sqrt();
            if !(length.is_finite() && length > 0.0) {
                return Err(SegmentError::BadUp { up });
            }
        }
        if labels.dimensions() != (width, height) {
            *labels = LabelImage::new(width, height);
        }
        let (w, h) = (width as usize, height as usize);
        self.resize(w, h);
        self.read(frame);
        let plane = match self.plane(frame, w, h) {
            Ok(plane) => plane,
            Err(reason) => {
                labels.fill(0);
                return Ok(Segmentation::NoSupport(reason));
            }
        };
        let objects = self.split(frame, plane, w, h, labels);
        Ok(Segmentation::Objects { objects, plane })
    }

    fn resize(&mut self, w: usize, h: usize) {
        let n = w * h;
        self.z.resize(n, 0.0);
        self.smooth.resize(n, 0.0);
        self.height.resize(n, 0.0);
        self.height_mean.resize(n, 0.0);
        self.read.resize(n, false);
        self.normals.resize(n, [0.0; 3]);
        self.seed.resize(n, false);
        self.grow.resize(n, false);
        self.cut.resize(n, false);
        self.xu.resize(w, 0.0);
        self.yv.resize(h, 0.0);
        self.boxes.resize(w, h);
        self.components.resize(n);
    }

    /// Depth to metres, and each pixel's ray.
    fn read(&mut self, frame: &RgbdFrame<'_>) {
        let scale = frame.depth.metres_per_unit() as f32;
        for (z, &d) in self.z.iter_mut().zip(frame.depth.pixels().as_raw()) {
            *z = f32::from(d) * scale;
        }
        let k = frame.intrinsics;
        for (u, x) in self.xu.iter_mut().enumerate() {
            *x = ((u as f64 - k.cx()) / k.fx()) as f32;
        }
        for (v, y) in self.yv.iter_mut().enumerate() {
            *y = ((v as f64 - k.cy()) / k.fy()) as f32;
        }
    }

    fn plane(&mut self, frame: &RgbdFrame<'_>, w: usize, h: usize) -> Result<Plane, NoSupport> {
        let s = &self.settings;
        let stride = s.plane_stride.max(1) as usize;
        let tolerance = s.plane_tolerance_m as f32;
        self.samples.clear();
        for v in (stride / 2..h).step_by(stride) {
            for u in (stride / 2..w).step_by(stride) {
                let z = self.z[v * w + u];
                if z > 0.0 {
                    self.samples.push(plane::Sample {
                        p: [self.xu[u] * z, self.yv[v] * z, z],
                        tolerance: tolerance * z * z,
                    });
                }
            }
        }
        if self.samples.len() < MIN_PLANE_SAMPLES {
            return Err(NoSupport::NoReadings {
                samples: self.samples.len(),
                needed: MIN_PLANE_SAMPLES,
            });
        }
        let needed = s.min_plane_share;
        let Some(plane) = plane::fit(&self.samples, s.plane_iterations, s.plane_seed) else {
            return Err(NoSupport::NoPlane { share: 0.0, needed });
        };
        if plane.share < needed {
            return Err(NoSupport::NoPlane {
                share: plane.share,
                needed,
            });
        }
        match frame.up {
            Some(up) => {
                let length = up.iter().map(|c| c * c).sum::<f64>().sqrt();
                let cos = plane
                    .normal
                    .iter()
                    .zip(up)
                    .map(|(n, u)| n * u / length)
                    .sum::<f64>();
                let angle_deg = cos.clamp(-1.0, 1.0).acos().to_degrees();
                if angle_deg > s.max_up_angle_deg {
                    return Err(NoSupport::NotLevel {
                        angle_deg,
                        max_deg: s.max_up_angle_deg,
                    });
                }
            }
            None => {
                // The normal faces the camera: its angle to the optical
                // axis is the plane's tilt against the image plane.
                let tilt_deg = plane.normal[2].abs().clamp(0.0, 1.0).acos().to_degrees();
                if tilt_deg < s.min_plane_tilt_deg {
                    return Err(NoSupport::FacesCamera {
                        tilt_deg,
                        min_deg: s.min_plane_tilt_deg,
                    });
                }
            }
        }
        Ok(plane)
    }

    fn split(
        &mut self,
        frame: &RgbdFrame<'_>,
        plane: Plane,
        w: usize,
        h: usize,
        labels: &mut LabelImage,
    ) -> usize {
        let s = self.settings;
        let n = plane.normal.map(|c| c as f32);
        let d = plane.offset as f32;
        let (min_height, grow_height) = (s.min_height_m as f32, s.grow_height_m as f32);
        let tolerance = s.plane_tolerance_m as f32;
        for v in 0..h {
            let ky = n[1] * self.yv[v] + n[2];
            let row = v * w;
            for u in 0..w {
                let i = row + u;
                let z = self.z[i];
                let above = z * (n[0] * self.xu[u] + ky) + d;
                let read = z > 0.0;
                self.read[i] = read;
                self.height[i] = if read { above } else { 0.0 };
            }
        }
        let support = warp::Support {
            z: &self.z,
            xu: &self.xu,
            yv: &self.yv,
            normal: n,
            tolerance,
            band: s.support_warp as f32,
            stride: s.plane_stride.max(1) as usize,
        };
        warp::flatten(&support, &mut self.height);
        for ((grow, &read), &above) in self.grow.iter_mut().zip(&self.read).zip(&self.height) {
            *grow = read && above > grow_height;
        }
        // A seed is a reading above `min_height` whose height averaged
        // over the 3 x 3 readings around it is above the noise term: a
        // reading's independent noise (`tolerance z^2` is four of its
        // sigmas on the reference camera) shrinks by 3 in the mean, and so
        // does the noise term. A far object's lower part then seeds as a
        // near one's does.
        let r = SEED_RADIUS;
        normals::smooth(
            &self.height,
            &self.read,
            w,
            h,
            r,
            &mut self.boxes,
            &mut self.height_mean,
        );
        let shrink = (2 * r + 1) as f32;
        for ((seed, (&z, &mean)), (&read, &above)) in self
            .seed
            .iter_mut()
            .zip(self.z.iter().zip(&self.height_mean))
            .zip(self.read.iter().zip(&self.height))
        {
            *seed = read && above > min_height && mean > tolerance * z * z / shrink;
        }
        normals::smooth(
            &self.z,
            &self.grow,
            w,
            h,
            s.smooth_radius as usize,
            &mut self.boxes,
            &mut self.smooth,
        );
        let jump_ratio = s.jump_ratio as f32;
        normals::normals(
            &self.smooth,
            &self.xu,
            &self.yv,
            w,
            h,
            s.normal_step as usize,
            jump_ratio,
            &mut self.normals,
        );
        let input = split::CutInput {
            z: &self.z,
            smooth: &self.smooth,
            normals: &self.normals,
            xu: &self.xu,
            yv: &self.yv,
            rgb: frame.colour.as_raw(),
            width: w,
            height: h,
        };
        let rule = split::CutRule {
            jump_ratio,
            tolerance,
            crease: s.crease as f32,
            weak_crease: s.weak_crease as f32,
            crease_step: s.crease_step as usize,
            colour_edge: s.colour_edge as f32,
        };
        split::cuts(&input, rule, &self.grow, &mut self.cut);
        for (seed, &cut) in self.seed.iter_mut().zip(&self.cut) {
            *seed &= !cut;
        }
        let layers = components::Layers {
            z: &self.z,
            height: &self.height,
            seed: &self.seed,
            grow: &self.grow,
            rgb: frame.colour.as_raw(),
            width: w,
        };
        let rule = components::Rule {
            jump_ratio,
            min_pixels: s.min_pixels,
            grow_steps: s.grow_steps.min(255) as u8,
            tolerance,
            grow_height,
            fy: frame.intrinsics.fy() as f32,
            merge: merge::MergeRule {
                colour: s.merge_colour as f32,
                border: s.merge_border as f32,
                max_pixels: s.merge_max_pixels,
            },
        };
        components::label(layers, rule, &mut self.components, labels)
    }
}
