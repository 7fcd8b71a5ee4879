//! The appearance feature a camera computes from an object's mask: a
//! colour histogram (hue of saturated pixels, brightness of grey ones) and
//! a histogram of gradient orientations, each built from what the masked
//! surface reflects under the scene's light into this camera.

use std::f64::consts::{PI, TAU};

use nalgebra::{Point3, Vector3};
use rand::Rng;

use crate::camera::Camera;
use crate::config::{ClassSpec, FeatureSpec, LightingSpec, Look};
use crate::random::{standard_normal, uniform};
use crate::sensor::{MaskPoint, Shows};
use crate::shape::Part;
use crate::world::WorldObject;

/// Saturation below which a pixel counts as grey, and above which fully
/// as coloured (linear blend between).
const GREY_SATURATION: [f64; 2] = [0.15, 0.35];
/// Brightness below which hue is too noisy to mean anything.
const DARK_VALUE: [f64; 2] = [0.04, 0.12];
/// Most brightness levels of saturated pixels (checked by the config).
pub(crate) const MAX_VALUE_LEVELS: usize = 16;
/// The sRGB-like encoding cameras apply before colour is binned.
const GAMMA: f64 = 1.0 / 2.2;

/// The scene's main light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Light {
    /// Unit vector towards the light.
    pub direction: Vector3<f64>,
    pub ambient: f64,
}

impl Light {
    pub(crate) fn draw<R: Rng>(spec: &LightingSpec, rng: &mut R) -> Self {
        let azimuth = TAU * rng.random::<f64>();
        let elevation = uniform(rng, spec.elevation_deg).to_radians();
        Self {
            direction: Vector3::new(
                elevation.cos() * azimuth.cos(),
                elevation.cos() * azimuth.sin(),
                elevation.sin(),
            ),
            ambient: spec.ambient,
        }
    }

    /// Lambertian shading of a surface with unit normal `normal`.
    fn shade(&self, normal: &Vector3<f64>) -> f64 {
        self.ambient + (1.0 - self.ambient) * normal.dot(&self.direction).max(0.0)
    }
}

/// Everything one camera's feature computation needs.
pub(crate) struct Viewing<'a> {
    pub camera: &'a Camera,
    pub light: &'a Light,
    pub spec: &'a FeatureSpec,
    pub surface: &'a Look,
    /// The camera's histogram sampling noise knob.
    pub pixel_noise: f64,
}

/// The feature of an object of `class` whose mask is `mask`.
pub(crate) fn feature<R: Rng>(
    mask: &[MaskPoint],
    object: &WorldObject,
    class: &ClassSpec,
    viewing: &Viewing<'_>,
    rng: &mut R,
) -> Vec<f32> {
    let spec = viewing.spec;
    let camera = viewing.camera;
    let mut colour = vec![0.0; spec.hue_bins * spec.value_levels + spec.grey_bins];
    let mut gradient = vec![0.0; spec.orientation_bins];
    let mean_gain = camera.colour_gain.iter().sum::<f64>() / 3.0;
    for p in mask {
        let (look, normal, tangents, tint) = match p.shows {
            Shows::Object(s) => (look_of(class, s.part), s.normal, s.tangents, object.tint),
            Shows::Support => (
                viewing.surface,
                Vector3::z(),
                [Vector3::x(), Vector3::y()],
                [1.0; 3],
            ),
        };
        let shade = viewing.light.shade(&normal);
        let patch_area: f64 = look.patches.iter().map(|q| q.area).sum();
        for patch in &look.patches {
            let mut rgb = [0.0; 3];
            for c in 0..3 {
                rgb[c] = (patch.rgb[c] * tint[c] * camera.colour_gain[c] * shade)
                    .min(1.0)
                    .powf(GAMMA);
            }
            add_colour(&mut colour, spec, rgb, p.pixels * patch.area / patch_area);
        }
        // Edge contrast scales with the light the surface returns.
        let contrast = p.pixels * shade * mean_gain;
        for edges in &look.edges {
            let a = edges.angle_deg.to_radians();
            let along = tangents[0] * a.cos() + tangents[1] * a.sin();
            if let Some(theta) = image_orientation(camera, &p.camera, &along) {
                add_orientation(&mut gradient, theta + 0.5 * PI, contrast * edges.strength);
            }
        }
        if let Shows::Object(_) = p.shows {
            // Near the outline the surface turns away from the camera; the
            // outline runs perpendicular to both normal and line of sight.
            let view = (camera.position - p.world).normalize();
            let grazing = 1.0 - normal.dot(&view).clamp(0.0, 1.0);
            let along = normal.cross(&view);
            if let Some(theta) = image_orientation(camera, &p.camera, &along) {
                let weight = contrast * spec.outline_strength * grazing * grazing;
                add_orientation(&mut gradient, theta + 0.5 * PI, weight);
            }
        }
    }
    let pixels: f64 = mask.iter().map(|p| p.pixels).sum();
    sampling_noise(&mut colour, pixels, viewing.pixel_noise, rng);
    sampling_noise(&mut gradient, pixels, viewing.pixel_noise, rng);
    normalise(&mut colour, spec.colour_weight);
    normalise(&mut gradient, spec.gradient_weight);
    colour.iter().chain(&gradient).map(|&v| v as f32).collect()
}

/// The look of the class on the given part of its surface.
fn look_of(class: &ClassSpec, part: Part) -> &Look {
    match part {
        Part::Top => &class.top,
        Part::Side { azimuth } => {
            let k = class.sides.len();
            // Sector 0 is centred on the front (azimuth 0).
            let sector = (azimuth / TAU * k as f64 + 0.5).floor() as i64;
            let index = sector.rem_euclid(k as i64) as usize;
            class.sides.get(index).unwrap_or(&class.top)
        }
    }
}

/// Orientation (radians) in the image of a small step `dir` (world axes)
/// taken at `q` (camera frame); `None` if it projects to a point.
fn image_orientation(camera: &Camera, q: &Point3<f64>, dir: &Vector3<f64>) -> Option<f64> {
    let d = camera.direction_to_camera(dir);
    let du = d.x * q.z - q.x * d.z;
    let dv = d.y * q.z - q.y * d.z;
    (du.hypot(dv) > 1e-12 * q.z * q.z).then(|| dv.atan2(du))
}

fn ramp(x: f64, [lo, hi]: [f64; 2]) -> f64 {
    ((x - lo) / (hi - lo)).clamp(0.0, 1.0)
}

/// Adds `weight` at a fractional position on a circle of bins, split
/// linearly between the two nearest bin centres.
fn add_circular(bins: &mut [f64], position: f64, weight: f64) {
    let n = bins.len();
    if n == 0 {
        return;
    }
    let x = position - 0.5;
    let lower = x.floor();
    let frac = x - lower;
    let i = (lower as i64).rem_euclid(n as i64) as usize;
    bins[i] += weight * (1.0 - frac);
    bins[(i + 1) % n] += weight * frac;
}

/// Adds `weight` at a fractional position on a line of bins.
fn add_linear(bins: &mut [f64], position: f64, weight: f64) {
    let n = bins.len();
    if n == 0 {
        return;
    }
    let x = (position - 0.5).clamp(0.0, (n - 1) as f64);
    let i = (x.floor() as usize).min(n - 1);
    let frac = x - i as f64;
    bins[i] += weight * (1.0 - frac);
    if i + 1 < n {
        bins[i + 1] += weight * frac;
    }
}

fn add_colour(hist: &mut [f64], spec: &FeatureSpec, rgb: [f64; 3], weight: f64) {
    let [r, g, b] = rgb;
    let value = r.max(g).max(b);
    let chroma = value - r.min(g).min(b);
    let saturation = if value > 0.0 { chroma / value } else { 0.0 };
    let coloured = ramp(saturation, GREY_SATURATION) * ramp(value, DARK_VALUE);
    let (hue_part, grey_part) = hist.split_at_mut(spec.hue_bins * spec.value_levels);
    if coloured > 0.0 && chroma > 0.0 {
        let sector = if value == r {
            ((g - b) / chroma).rem_euclid(6.0)
        } else if value == g {
            (b - r) / chroma + 2.0
        } else {
            (r - g) / chroma + 4.0
        };
        // Split between brightness levels first, then around the hue circle
        // within each level: brown and orange share a hue, not a level.
        let mut storage = [0.0; MAX_VALUE_LEVELS];
        let levels = &mut storage[..spec.value_levels.min(MAX_VALUE_LEVELS)];
        add_linear(levels, value * spec.value_levels as f64, weight * coloured);
        for (row, &w) in hue_part.chunks_mut(spec.hue_bins).zip(levels.iter()) {
            if w > 0.0 {
                add_circular(row, sector / 6.0 * spec.hue_bins as f64, w);
            }
        }
    }
    add_linear(
        grey_part,
        value * spec.grey_bins as f64,
        weight * (1.0 - coloured),
    );
}

/// Gradients are unsigned: orientations a half turn apart are one bin.
fn add_orientation(hist: &mut [f64], theta: f64, weight: f64) {
    let turn = theta.rem_euclid(PI) / PI;
    add_circular(hist, turn * hist.len() as f64, weight);
}

/// A histogram estimated from `pixels` pixels errs per bin by about
/// `sqrt(p (1 - p) / pixels)` of its mass; `scale` accounts for pixels not
/// being independent.
fn sampling_noise<R: Rng>(hist: &mut [f64], pixels: f64, scale: f64, rng: &mut R) {
    let mass: f64 = hist.iter().sum();
    for h in hist.iter_mut() {
        let z = standard_normal(rng);
        if mass > 0.0 && pixels > 0.0 {
            let p = *h / mass;
            *h = (*h + scale * z * mass * (p * (1.0 - p) / pixels).sqrt()).max(0.0);
        }
    }
}

fn normalise(hist: &mut [f64], norm: f64) {
    let sum: f64 = hist.iter().sum();
    if sum > 0.0 {
        hist.iter_mut().for_each(|h| *h *= norm / sum);
    }
}
