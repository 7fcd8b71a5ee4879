//! The person's pointing gestures: one chosen object per time slot, aimed
//! at from the hand with a per-gesture error.

use nalgebra::{Point3, Unit, Vector3};
use rand::Rng;
use vref_scene::Side;

use super::LiveWorld;
use crate::camera::Camera;
use crate::random::{Purpose, keyed, normal};

/// A pointing ray as the headset's gesture recogniser reports it, with
/// the object the person means.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gesture {
    /// `floor(t / gesture_period_s)`: the person points at one object per
    /// slot.
    pub slot: i64,
    /// World index of the object pointed at.
    pub target: usize,
    /// The target's track ids: what a correct answer names.
    pub human_id: u64,
    pub robot_id: u64,
    /// The hand, in the headset camera's frame (x right, y down, z forward).
    pub origin: Point3<f64>,
    /// In the headset camera's frame.
    pub direction: Unit<Vector3<f64>>,
    /// Radians.
    pub cone_half_angle: f64,
    pub confidence: f64,
}

impl LiveWorld {
    /// The gesture at `t`, if any object stays for the whole slot.
    ///
    /// The target is drawn per slot among the objects present throughout
    /// it, preferring those both cameras detect at the slot's start, then
    /// those the headset detects. The ray starts at the hand and aims at
    /// the target's true centre at `t` (so it follows the drift), off by
    /// an angular error drawn once per slot.
    pub fn gesture(&self, t: f64) -> Option<Gesture> {
        let dynamics = &self.dynamics;
        let period = dynamics.gesture_period_s;
        let slot = (t / period).floor();
        let (start, end) = (slot * period, (slot + 1.0) * period);
        let staying: Vec<usize> = (0..self.object_count())
            .filter(|&k| !self.away_during(k, start, end))
            .collect();
        let robot = self.detected(Side::Robot, start);
        let human = self.detected(Side::Human, start);
        let seen_by = |list: &[usize], k: &usize| list.binary_search(k).is_ok();
        let both: Vec<usize> = staying
            .iter()
            .copied()
            .filter(|k| seen_by(&human, k) && seen_by(&robot, k))
            .collect();
        let by_headset: Vec<usize> = staying
            .iter()
            .copied()
            .filter(|k| seen_by(&human, k))
            .collect();
        let choices = [both, by_headset, staying]
            .into_iter()
            .find(|c| !c.is_empty())?;

        // Saturating float-to-int casts keep absurd times harmless.
        let slot = slot as i64;
        let mut rng = keyed(self.seed, Purpose::Gesture, 0, slot as u64);
        let target = choices[rng.random_range(0..choices.len())];
        let sigma = dynamics.pointing_noise_deg.to_radians();
        let error = [normal(&mut rng, sigma), normal(&mut rng, sigma)];

        let camera = self.camera(Side::Human, t);
        let centre = self.object(target, t)?.centre;
        let hand = hand(&camera, dynamics.hand_offset);
        let aim = Unit::try_new(centre - hand, 1e-12)?;
        let direction = camera.direction_to_camera(&off_by(&aim, error));
        Some(Gesture {
            slot,
            target,
            human_id: self.track_id(Side::Human, target)?,
            robot_id: self.track_id(Side::Robot, target)?,
            origin: camera.to_camera(&hand),
            direction: Unit::try_new(direction, 1e-12)?,
            cone_half_angle: dynamics.cone_half_angle_deg.to_radians(),
            confidence: dynamics.gesture_confidence,
        })
    }
}

/// The hand in the world frame: `offset` is right, down (vertical) and
/// forward (horizontal) of the headset, as the person faces.
fn hand(camera: &Camera, [right, down, forward]: [f64; 3]) -> Point3<f64> {
    let to_world = camera.rotation.inverse();
    let axis = to_world * Vector3::z();
    // Looking straight down leaves the heading to the camera's right axis.
    let heading = Vector3::new(axis.x, axis.y, 0.0)
        .try_normalize(1e-9)
        .or_else(|| {
            Vector3::z()
                .cross(&(to_world * Vector3::x()))
                .try_normalize(1e-9)
        })
        .unwrap_or_else(Vector3::x);
    let right_axis = heading.cross(&Vector3::z());
    camera.position + right_axis * right - Vector3::z() * down + heading * forward
}

/// `aim` turned by the small angles `error` (radians) about two axes
/// across it.
fn off_by(aim: &Unit<Vector3<f64>>, error: [f64; 2]) -> Vector3<f64> {
    let across = aim
        .cross(&Vector3::z())
        .try_normalize(1e-9)
        .unwrap_or_else(|| aim.cross(&Vector3::x()).normalize());
    let other = aim.cross(&across);
    aim.into_inner() + across * error[0].tan() + other * error[1].tan()
}
