//! What one camera sees: per object, the surface samples facing it, inside
//! its image and depth range, and not hidden behind another object.

use nalgebra::Point3;

use crate::camera::Camera;
use crate::config::CameraSpec;
use crate::shape::SurfacePoint;
use crate::world::{WorldObject, WorldPoint};

/// A surface sample that reaches the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SeenPoint {
    pub world: Point3<f64>,
    /// Position in the camera frame.
    pub camera: Point3<f64>,
    /// Pixel offsets from the image centre.
    pub image: [f64; 2],
    /// Pixels this sample covers.
    pub pixels: f64,
    pub sample: SurfacePoint,
}

/// An object the camera's detector finds.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Detection {
    /// Index into the world's objects.
    pub object: usize,
    pub points: Vec<SeenPoint>,
    /// Share (by pixels) of the camera-facing surface that is seen.
    pub visible_fraction: f64,
    pub pixels: f64,
}

/// The objects `camera` detects, in world order.
pub(crate) fn detect(
    camera: &Camera,
    objects: &[WorldObject],
    surfaces: &[Vec<WorldPoint>],
    spec: &CameraSpec,
) -> Vec<Detection> {
    let mut detections = Vec::new();
    for (k, surface) in surfaces.iter().enumerate() {
        let occluders = occluders(camera, objects, k);
        let mut facing = 0.0;
        let mut points = Vec::new();
        for wp in surface {
            let to_camera = camera.position - wp.position;
            let distance = to_camera.norm();
            let cos = wp.sample.normal.dot(&to_camera) / distance;
            // Convex solids: a sample facing away is hidden by its own body.
            if cos <= 0.0 {
                continue;
            }
            let pixels = wp.sample.area * cos * (camera.focal_px / distance).powi(2);
            facing += pixels;
            let q = camera.to_camera(&wp.position);
            if !camera.sees(&q) {
                continue;
            }
            let hidden = occluders
                .iter()
                .any(|other| other.blocks(&camera.position, &wp.position));
            if hidden {
                continue;
            }
            if let Some(image) = camera.project(&q) {
                points.push(SeenPoint {
                    world: wp.position,
                    camera: q,
                    image,
                    pixels,
                    sample: wp.sample,
                });
            }
        }
        let seen: f64 = points.iter().map(|p| p.pixels).sum();
        let visible_fraction = if facing > 0.0 { seen / facing } else { 0.0 };
        if !points.is_empty()
            && visible_fraction >= spec.min_visible_fraction
            && seen >= spec.min_pixels
        {
            detections.push(Detection {
                object: k,
                points,
                visible_fraction,
                pixels: seen,
            });
        }
    }
    detections
}

/// The objects other than `k` that could hide some part of it from the
/// camera: only these need the exact test for each of its samples (with
/// tens of objects, most pairs are far apart in the image).
fn occluders<'a>(camera: &Camera, objects: &'a [WorldObject], k: usize) -> Vec<&'a WorldObject> {
    let Some(target) = objects.get(k) else {
        return Vec::new();
    };
    let radius = target.shape.bounding_radius();
    objects
        .iter()
        .enumerate()
        .filter(|&(j, other)| {
            j != k && other.may_hide_ball(&camera.position, &target.centre, radius)
        })
        .map(|(_, other)| other)
        .collect()
}
