//! The workspace's contents: which objects stand where.

use std::f64::consts::TAU;

use nalgebra::{Point3, Rotation3, Vector3};
use rand::Rng;

use crate::config::{SimConfig, WorkspaceSpec};
use crate::random::{count, normal, uniform};
use crate::shape::{Shape, SurfacePoint};

/// One physical object of a generated scene.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldObject {
    /// Index of its class in [`SimConfig::classes`].
    pub class: usize,
    /// This instance's solid (the class's, scaled).
    pub shape: Shape,
    /// Centre of the solid in the world frame.
    pub centre: Point3<f64>,
    /// Rotation about the vertical axis: where the object's front faces.
    pub yaw: f64,
    /// Per-channel reflectance factor of this instance.
    pub tint: [f64; 3],
}

/// A surface sample in the world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct WorldPoint {
    pub position: Point3<f64>,
    pub sample: SurfacePoint,
}

impl WorldObject {
    fn rotation(&self) -> Rotation3<f64> {
        Rotation3::from_axis_angle(&Vector3::z_axis(), self.yaw)
    }

    /// Surface samples with offset, normal and tangents in world axes; the
    /// part keeps its object-frame azimuth, which picks the look.
    pub(crate) fn surface(&self) -> Vec<WorldPoint> {
        let rotation = self.rotation();
        self.shape
            .surface()
            .into_iter()
            .map(|s| WorldPoint {
                position: self.centre + rotation * s.offset,
                sample: SurfacePoint {
                    offset: rotation * s.offset,
                    normal: rotation * s.normal,
                    tangents: s.tangents.map(|t| rotation * t),
                    ..s
                },
            })
            .collect()
    }

    /// Whether the solid could hide any point within `radius` of `centre`
    /// from `eye`: every segment from `eye` to such a point stays within
    /// `radius` of the segment to `centre`, so a solid whose bounding
    /// sphere is farther than both radii from that segment hides none of
    /// them ([`Self::blocks`] would say `false` for each). The margin
    /// covers rounding, so that the pre-test never changes a result.
    pub(crate) fn may_hide_ball(
        &self,
        eye: &Point3<f64>,
        centre: &Point3<f64>,
        radius: f64,
    ) -> bool {
        const MARGIN: f64 = 1e-6;
        let dir = centre - eye;
        let to_centre = self.centre - eye;
        let t = (to_centre.dot(&dir) / dir.norm_squared()).clamp(0.0, 1.0);
        (to_centre - dir * t).norm() <= self.shape.bounding_radius() + radius + MARGIN
    }

    /// Whether the open segment from `a` to `b` passes through the solid.
    pub(crate) fn blocks(&self, a: &Point3<f64>, b: &Point3<f64>) -> bool {
        let dir = b - a;
        // Cheap rejection: the segment misses the bounding sphere.
        let to_centre = self.centre - a;
        let t = (to_centre.dot(&dir) / dir.norm_squared()).clamp(0.0, 1.0);
        if (to_centre - dir * t).norm() > self.shape.bounding_radius() {
            return false;
        }
        let inverse = self.rotation().inverse();
        let origin = inverse * (a - self.centre);
        let local_dir = inverse * dir;
        // The ends touch surfaces (the camera, the seen point): only a
        // crossing strictly between them hides the point.
        const END: f64 = 1e-6;
        self.shape
            .line_interval(&origin, &local_dir)
            .is_some_and(|(t_in, t_out)| t_in < 1.0 - END && t_out > END)
    }
}

/// Draws how many instances of each class stand in the scene, then places
/// them at random without overlap. `None` when some object found no free
/// place within the attempts allowed (the caller redraws).
pub(crate) fn place_objects<R: Rng>(config: &SimConfig, rng: &mut R) -> Option<Vec<WorldObject>> {
    let objects = draw_objects(config, rng);
    arrange(objects, &config.workspace, rng)
}

/// As many instances of each class as its instance range draws.
pub(crate) fn draw_objects<R: Rng>(config: &SimConfig, rng: &mut R) -> Vec<WorldObject> {
    let mut objects = Vec::new();
    for (class, spec) in config.classes.iter().enumerate() {
        for _ in 0..count(rng, spec.instances) {
            objects.push(draw_instance(config, class, rng));
        }
    }
    objects
}

/// One instance of class `class`, standing at the workspace centre.
pub(crate) fn draw_instance<R: Rng>(config: &SimConfig, class: usize, rng: &mut R) -> WorldObject {
    let spec = &config.classes[class];
    let size = normal(rng, spec.size_variation).exp();
    let tint = [0; 3].map(|_| normal(rng, spec.instance_variation).exp());
    let shape = spec.shape.scaled(size);
    WorldObject {
        class,
        shape,
        centre: Point3::new(0.0, 0.0, shape.half_height()),
        yaw: TAU * rng.random::<f64>(),
        tint,
    }
}

/// Places `objects` at random in the workspace's area, their footprints
/// at least `min_gap` apart. `None` when some object found no free place.
pub(crate) fn arrange<R: Rng>(
    mut objects: Vec<WorldObject>,
    ws: &WorkspaceSpec,
    rng: &mut R,
) -> Option<Vec<WorldObject>> {
    // Largest first: they are the hardest to fit once others stand.
    let mut order: Vec<usize> = (0..objects.len()).collect();
    order.sort_by(|&a, &b| {
        objects[b]
            .shape
            .footprint_radius()
            .total_cmp(&objects[a].shape.footprint_radius())
    });
    let mut placed: Vec<usize> = Vec::with_capacity(objects.len());
    for &k in &order {
        let r = objects[k].shape.footprint_radius();
        let (hx, hy) = (0.5 * ws.area[0] - r, 0.5 * ws.area[1] - r);
        if hx < 0.0 || hy < 0.0 {
            return None;
        }
        let mut found = false;
        for _ in 0..ws.placement_attempts {
            let (x, y) = (uniform(rng, [-hx, hx]), uniform(rng, [-hy, hy]));
            let free = placed.iter().all(|&j| {
                let other = &objects[j];
                let gap = r + other.shape.footprint_radius() + ws.min_gap;
                (x - other.centre.x).hypot(y - other.centre.y) >= gap
            });
            if free {
                objects[k].centre.x = x;
                objects[k].centre.y = y;
                found = true;
                break;
            }
        }
        if !found {
            return None;
        }
        placed.push(k);
    }
    Some(objects)
}
