//! What one camera reports of the objects it detects in one frame.

use nalgebra::Point3;
use rand::Rng;

use crate::appearance::{Light, Viewing, feature};
use crate::camera::Camera;
use crate::config::{CameraSpec, SimConfig};
use crate::random::normal;
use crate::sensor::{locate, segment};
use crate::visibility::Detection;
use crate::world::WorldObject;

/// One detection as the camera reports it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Measurement {
    /// In the camera frame.
    pub position: Point3<f64>,
    pub feature: Vec<f32>,
}

/// Measures `detections` (of `objects`, by `camera`) in detection order:
/// one depth scale error for the whole frame, then per detection its mask,
/// the mask's centroid and its feature.
pub(crate) fn measure<R: Rng>(
    config: &SimConfig,
    objects: &[WorldObject],
    light: &Light,
    camera: &Camera,
    spec: &CameraSpec,
    detections: &[Detection],
    rng: &mut R,
) -> Vec<Measurement> {
    let frame_scale = normal(rng, spec.noise.depth_scale).exp();
    let viewing = Viewing {
        camera,
        light,
        spec: &config.features,
        surface: &config.workspace.surface,
        pixel_noise: spec.noise.pixel,
    };
    detections
        .iter()
        .map(|detection| {
            let object = &objects[detection.object];
            let mask = segment(detection, camera, &spec.noise, rng);
            let centre = camera.to_camera(&object.centre);
            let position = locate(&mask, &centre, &spec.noise, frame_scale, rng);
            let class = &config.classes[object.class];
            let feature = feature(&mask, object, class, &viewing, rng);
            Measurement { position, feature }
        })
        .collect()
}
