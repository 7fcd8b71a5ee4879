//! A layout made into a scene: lit, both cameras posed around it, and what
//! each camera detects.

use rand::Rng;

use crate::appearance::Light;
use crate::camera::{Camera, place_camera};
use crate::config::SimConfig;
use crate::random::uniform;
use crate::visibility::{Detection, detect};
use crate::world::WorldObject;

/// A lit layout with both cameras posed.
#[derive(Debug, Clone)]
pub(crate) struct Stage {
    pub objects: Vec<WorldObject>,
    pub light: Light,
    pub robot: Camera,
    pub human: Camera,
    pub robot_detections: Vec<Detection>,
    pub human_detections: Vec<Detection>,
}

/// Draws the light and both camera poses for `objects`. `None` when a view
/// detects fewer than `min_objects_per_view` objects (the caller redraws).
pub(crate) fn stage<R: Rng>(
    config: &SimConfig,
    objects: Vec<WorldObject>,
    rng: &mut R,
) -> Option<Stage> {
    let light = Light::draw(&config.lighting, rng);
    let vp = &config.viewpoints;
    let robot_azimuth = uniform(rng, vp.robot_azimuth_deg).to_radians();
    let human_azimuth = robot_azimuth + uniform(rng, vp.human_offset_deg).to_radians();
    let robot = place_camera(&config.robot, robot_azimuth, rng);
    let human = place_camera(&config.human, human_azimuth, rng);
    let surfaces: Vec<_> = objects.iter().map(WorldObject::surface).collect();
    let robot_detections = detect(&robot, &objects, &surfaces, &config.robot);
    let human_detections = detect(&human, &objects, &surfaces, &config.human);
    let min = config.min_objects_per_view;
    if robot_detections.len() < min || human_detections.len() < min {
        return None;
    }
    Some(Stage {
        objects,
        light,
        robot,
        human,
        robot_detections,
        human_detections,
    })
}
