//! How a camera turns what it sees into one object of its graph: a
//! segmentation mask (with errors along the outline) whose depth pixels are
//! averaged into a centroid (with depth error).

use std::f64::consts::TAU;

use nalgebra::Point3;
use rand::Rng;

use crate::camera::Camera;
use crate::config::SensorNoise;
use crate::random::{normal, standard_normal};
use crate::shape::SurfacePoint;
use crate::visibility::{Detection, SeenPoint};

/// Largest share of a mask the segmentation may get wrong: beyond it the
/// detector would not report the object at all.
const MAX_SEGMENTATION_ERROR: f64 = 0.5;

/// The depth factor of one object never drops below this, so the measured
/// position stays in front of the camera whatever the noise.
const MIN_DEPTH_FACTOR: f64 = 0.1;

/// What a mask pixel shows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Shows {
    Object(SurfacePoint),
    /// The support surface behind the object's outline.
    Support,
}

/// A group of mask pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MaskPoint {
    pub world: Point3<f64>,
    /// Position in the camera frame.
    pub camera: Point3<f64>,
    pub pixels: f64,
    pub shows: Shows,
}

/// The object's mask: its seen surface, with one side of the outline either
/// cut off or bled into the background behind it.
pub(crate) fn segment<R: Rng>(
    detection: &Detection,
    camera: &Camera,
    noise: &SensorNoise,
    rng: &mut R,
) -> Vec<MaskPoint> {
    let share = normal(rng, noise.segmentation)
        .abs()
        .min(MAX_SEGMENTATION_ERROR);
    let side = TAU * rng.random::<f64>();
    let bleeds = rng.random_bool(0.5);

    let (sin, cos) = side.sin_cos();
    let along = |p: &SeenPoint| p.image[0] * cos + p.image[1] * sin;
    let mut order: Vec<usize> = (0..detection.points.len()).collect();
    order.sort_by(|&a, &b| along(&detection.points[b]).total_cmp(&along(&detection.points[a])));
    let total: f64 = detection.points.iter().map(|p| p.pixels).sum();
    // The outline strip: the outermost samples on that side, up to `share`
    // of the pixels.
    let mut strip = vec![false; detection.points.len()];
    let mut taken = 0.0;
    for &k in &order {
        let pixels = detection.points[k].pixels;
        if taken + pixels > share * total {
            break;
        }
        taken += pixels;
        strip[k] = true;
    }

    let mut mask = Vec::with_capacity(detection.points.len());
    for (p, &in_strip) in detection.points.iter().zip(&strip) {
        if !in_strip || bleeds {
            mask.push(MaskPoint {
                world: p.world,
                camera: p.camera,
                pixels: p.pixels,
                shows: Shows::Object(p.sample),
            });
        }
        if in_strip && bleeds {
            // The mislabelled pixels beside the outline look past the
            // object, along nearly the same ray, onto the surface behind.
            let (c, w) = (camera.position, p.world);
            if w.z < c.z {
                let background = c + (w - c) * (c.z / (c.z - w.z));
                let q = camera.to_camera(&background);
                if camera.sees(&q) {
                    mask.push(MaskPoint {
                        world: background,
                        camera: q,
                        pixels: p.pixels,
                        shows: Shows::Support,
                    });
                }
            }
        }
    }
    mask
}

/// The centroid of the mask's depth pixels, as the camera measures it:
/// drawn from the object's centre `centre` (camera frame) towards the
/// centroid by the surface bias, moved along its ray by a depth error
/// growing with the square of the depth, and scaled by the frame's depth
/// scale error.
pub(crate) fn locate<R: Rng>(
    mask: &[MaskPoint],
    centre: &Point3<f64>,
    noise: &SensorNoise,
    frame_scale: f64,
    rng: &mut R,
) -> Point3<f64> {
    let error = standard_normal(rng);
    let total: f64 = mask.iter().map(|p| p.pixels).sum();
    let centroid = if total > 0.0 {
        mask.iter().fold(Point3::origin(), |acc, p| {
            acc + p.camera.coords * (p.pixels / total)
        })
    } else {
        *centre
    };
    let seen = centre + (centroid - centre) * noise.surface_bias;
    let factor = (1.0 + error * noise.depth * seen.z).max(MIN_DEPTH_FACTOR);
    Point3::from(seen.coords * (factor * frame_scale))
}
