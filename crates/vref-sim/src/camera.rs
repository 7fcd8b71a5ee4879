//! A pinhole camera in the world, and where each camera of a scene stands.

use nalgebra::{Matrix3, Point3, Rotation3, Vector3};
use rand::Rng;

use crate::config::CameraSpec;
use crate::random::{normal, uniform};

/// A posed pinhole camera. Its frame: x right, y down, z forward (optical
/// axis), as RGB-D drivers report points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Optical centre in the world frame.
    pub position: Point3<f64>,
    /// World axes to camera axes.
    pub rotation: Rotation3<f64>,
    /// Focal length in pixels.
    pub focal_px: f64,
    /// Image size in pixels.
    pub width_px: f64,
    pub height_px: f64,
    /// Nearest and farthest measurable depth.
    pub depth_range: [f64; 2],
    /// Per-channel gain applied to the light reaching the sensor: the
    /// camera model's colour response times what its white balance and
    /// exposure left in this frame.
    pub colour_gain: [f64; 3],
}

impl Camera {
    /// A camera at `position` aimed at `target`, turned by `roll` (radians)
    /// about its optical axis.
    pub fn looking_at(
        position: Point3<f64>,
        target: Point3<f64>,
        roll: f64,
        spec: &CameraSpec,
        colour_gain: [f64; 3],
    ) -> Self {
        let forward = (target - position)
            .try_normalize(1e-12)
            .unwrap_or_else(|| -Vector3::z());
        // Looking straight down leaves "right" open; any horizontal axis does.
        let right = forward
            .cross(&Vector3::z())
            .try_normalize(1e-9)
            .unwrap_or_else(Vector3::x);
        let down = forward.cross(&right);
        let (s, c) = roll.sin_cos();
        let (right, down) = (right * c + down * s, down * c - right * s);
        let rows = Matrix3::from_rows(&[right.transpose(), down.transpose(), forward.transpose()]);
        let half_h = (0.5 * spec.hfov_deg).to_radians().tan();
        let half_v = (0.5 * spec.vfov_deg).to_radians().tan();
        let width_px = f64::from(spec.image_width);
        let focal_px = 0.5 * width_px / half_h;
        Self {
            position,
            rotation: Rotation3::from_matrix_unchecked(rows),
            focal_px,
            width_px,
            height_px: 2.0 * focal_px * half_v,
            depth_range: spec.depth_range,
            colour_gain,
        }
    }

    /// A world point in this camera's frame.
    pub fn to_camera(&self, p: &Point3<f64>) -> Point3<f64> {
        Point3::from(self.rotation * (p - self.position))
    }

    /// A world direction in this camera's frame.
    pub fn direction_to_camera(&self, d: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * d
    }

    /// Pixel offsets from the image centre (right, down) of a point in the
    /// camera frame, or `None` if it is not in front of the camera.
    pub fn project(&self, q: &Point3<f64>) -> Option<[f64; 2]> {
        (q.z > 0.0).then(|| [self.focal_px * q.x / q.z, self.focal_px * q.y / q.z])
    }

    /// Whether a point in the camera frame is in the image and in depth range.
    pub fn sees(&self, q: &Point3<f64>) -> bool {
        let [near, far] = self.depth_range;
        if !(near..=far).contains(&q.z) {
            return false;
        }
        self.project(q)
            .is_some_and(|[u, v]| u.abs() <= 0.5 * self.width_px && v.abs() <= 0.5 * self.height_px)
    }
}

/// Draws a pose around the workspace: at azimuth `azimuth` (radians, the
/// direction from the workspace centre to the camera), at the spec's
/// distance and height, aimed near the centre of the surface.
pub(crate) fn place_camera<R: Rng>(spec: &CameraSpec, azimuth: f64, rng: &mut R) -> Camera {
    let distance = uniform(rng, spec.distance);
    let height = uniform(rng, spec.height);
    let position = Point3::new(distance * azimuth.cos(), distance * azimuth.sin(), height);
    let target = Point3::new(
        normal(rng, spec.aim_jitter),
        normal(rng, spec.aim_jitter),
        0.0,
    );
    let roll = normal(rng, spec.roll_deg.to_radians());
    let exposure = normal(rng, spec.noise.exposure).exp();
    let mut gain = [0.0; 3];
    for (g, &base) in gain.iter_mut().zip(&spec.colour_gain) {
        *g = base * exposure * normal(rng, spec.noise.white_balance).exp();
    }
    Camera::looking_at(position, target, roll, spec, gain)
}
