//! Object solids: convex shapes standing upright on the support surface,
//! with the surface samples the cameras look at and the ray test occlusion
//! needs. Coordinates here are in the object's own frame: origin at the
//! centre of the solid, z up, x its front.

use std::f64::consts::{PI, TAU};

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::ConfigError;
use crate::config::positive;

/// The solid of an object class.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    Sphere {
        radius: f64,
    },
    /// Upright, axis vertical.
    Cylinder {
        radius: f64,
        height: f64,
    },
    /// Size along the object's own x (front), y and z axes.
    Cuboid {
        size: [f64; 3],
    },
}

/// Which look of its class a surface sample shows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Part {
    /// Vertical surface; azimuth of the outward normal in the object frame.
    Side {
        azimuth: f64,
    },
    Top,
}

/// A small piece of an object's surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SurfacePoint {
    pub offset: Vector3<f64>,
    /// Outward unit normal.
    pub normal: Vector3<f64>,
    /// Unit tangents that edge angles 0 and 90 degrees run along.
    pub tangents: [Vector3<f64>; 2],
    pub area: f64,
    pub part: Part,
}

/// Samples along each axis of a face or around a circle: enough that a
/// partly hidden object's visible share is resolved to a few percent.
const SPHERE_SAMPLES: usize = 240;
const RING_SAMPLES: usize = 32;
const HEIGHT_SAMPLES: usize = 6;
const DISC_RINGS: usize = 3;
const FACE_SAMPLES: usize = 6;

/// Normals steeper than this (cosine to vertical) belong to a sphere's top.
const SPHERE_TOP_COS: f64 = 0.8;

impl Shape {
    /// The shape scaled by `factor` in every dimension.
    pub fn scaled(&self, factor: f64) -> Shape {
        match *self {
            Shape::Sphere { radius } => Shape::Sphere {
                radius: radius * factor,
            },
            Shape::Cylinder { radius, height } => Shape::Cylinder {
                radius: radius * factor,
                height: height * factor,
            },
            Shape::Cuboid { size } => Shape::Cuboid {
                size: size.map(|s| s * factor),
            },
        }
    }

    /// Radius of the smallest vertical cylinder around the object: two
    /// objects whose footprint circles do not overlap do not overlap.
    pub fn footprint_radius(&self) -> f64 {
        match *self {
            Shape::Sphere { radius } | Shape::Cylinder { radius, .. } => radius,
            Shape::Cuboid { size } => 0.5 * size[0].hypot(size[1]),
        }
    }

    /// Height of the centre above the surface the object stands on.
    pub fn half_height(&self) -> f64 {
        match *self {
            Shape::Sphere { radius } => radius,
            Shape::Cylinder { height, .. } => 0.5 * height,
            Shape::Cuboid { size } => 0.5 * size[2],
        }
    }

    /// Radius of a sphere about the centre that holds the whole object.
    pub fn bounding_radius(&self) -> f64 {
        match *self {
            Shape::Sphere { radius } => radius,
            Shape::Cylinder { radius, height } => radius.hypot(0.5 * height),
            Shape::Cuboid { size } => {
                0.5 * (size[0].powi(2) + size[1].powi(2) + size[2].powi(2)).sqrt()
            }
        }
    }

    pub(crate) fn validate(&self, at: &str) -> Result<(), ConfigError> {
        match *self {
            Shape::Sphere { radius } => positive(&format!("{at}.radius"), radius),
            Shape::Cylinder { radius, height } => {
                positive(&format!("{at}.radius"), radius)?;
                positive(&format!("{at}.height"), height)
            }
            Shape::Cuboid { size } => {
                for (axis, &s) in size.iter().enumerate() {
                    positive(&format!("{at}.size[{axis}]"), s)?;
                }
                Ok(())
            }
        }
    }

    /// The parameter interval `(t_in, t_out)` over which the line
    /// `origin + t dir` is inside the solid, if it meets it.
    pub(crate) fn line_interval(
        &self,
        origin: &Vector3<f64>,
        dir: &Vector3<f64>,
    ) -> Option<(f64, f64)> {
        match *self {
            Shape::Sphere { radius } => quadratic_interval(
                dir.norm_squared(),
                origin.dot(dir),
                origin.norm_squared(),
                radius,
            ),
            Shape::Cylinder { radius, height } => {
                let (o2, d2) = (origin.xy(), dir.xy());
                let radial =
                    quadratic_interval(d2.norm_squared(), o2.dot(&d2), o2.norm_squared(), radius)?;
                let vertical = slab(origin.z, dir.z, 0.5 * height)?;
                intersect(radial, vertical)
            }
            Shape::Cuboid { size } => {
                let mut interval = (f64::NEG_INFINITY, f64::INFINITY);
                for axis in 0..3 {
                    let along = slab(origin[axis], dir[axis], 0.5 * size[axis])?;
                    interval = intersect(interval, along)?;
                }
                Some(interval)
            }
        }
    }

    /// Surface samples covering every face that is not standing on the
    /// support surface.
    pub(crate) fn surface(&self) -> Vec<SurfacePoint> {
        match *self {
            Shape::Sphere { radius } => sphere_surface(radius),
            Shape::Cylinder { radius, height } => cylinder_surface(radius, height),
            Shape::Cuboid { size } => cuboid_surface(size),
        }
    }
}

/// Interval where `|o + t d|^2 <= r^2`, given `a = d.d`, `half_b = o.d`,
/// `c0 = o.o`.
fn quadratic_interval(a: f64, half_b: f64, c0: f64, r: f64) -> Option<(f64, f64)> {
    let c = c0 - r * r;
    if a <= f64::EPSILON {
        // The line runs parallel to the axis: inside everywhere or nowhere.
        return (c <= 0.0).then_some((f64::NEG_INFINITY, f64::INFINITY));
    }
    let disc = half_b * half_b - a * c;
    if disc <= 0.0 {
        return None;
    }
    let root = disc.sqrt();
    Some(((-half_b - root) / a, (-half_b + root) / a))
}

/// Interval where `|o + t d| <= half` along one axis.
fn slab(o: f64, d: f64, half: f64) -> Option<(f64, f64)> {
    if d.abs() <= f64::EPSILON {
        return (o.abs() <= half).then_some((f64::NEG_INFINITY, f64::INFINITY));
    }
    let (t0, t1) = ((-half - o) / d, (half - o) / d);
    Some((t0.min(t1), t0.max(t1)))
}

fn intersect(a: (f64, f64), b: (f64, f64)) -> Option<(f64, f64)> {
    let (lo, hi) = (a.0.max(b.0), a.1.min(b.1));
    (lo < hi).then_some((lo, hi))
}

fn horizontal_tangent(normal: &Vector3<f64>) -> Vector3<f64> {
    let t = Vector3::z().cross(normal);
    let norm = t.norm();
    if norm > 1e-9 { t / norm } else { Vector3::x() }
}

fn side_point(offset: Vector3<f64>, normal: Vector3<f64>, area: f64) -> SurfacePoint {
    SurfacePoint {
        offset,
        normal,
        tangents: [horizontal_tangent(&normal), Vector3::z()],
        area,
        part: Part::Side {
            azimuth: normal.y.atan2(normal.x),
        },
    }
}

fn top_point(offset: Vector3<f64>, area: f64) -> SurfacePoint {
    SurfacePoint {
        offset,
        normal: Vector3::z(),
        tangents: [Vector3::x(), Vector3::y()],
        area,
        part: Part::Top,
    }
}

/// Evenly spread points (Fibonacci lattice).
fn sphere_surface(radius: f64) -> Vec<SurfacePoint> {
    let golden = PI * (3.0 - 5f64.sqrt());
    let area = 4.0 * PI * radius * radius / SPHERE_SAMPLES as f64;
    (0..SPHERE_SAMPLES)
        .map(|i| {
            let z = 1.0 - (2 * i + 1) as f64 / SPHERE_SAMPLES as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * i as f64;
            let normal = Vector3::new(r * phi.cos(), r * phi.sin(), z);
            let t = horizontal_tangent(&normal);
            let part = if z > SPHERE_TOP_COS {
                Part::Top
            } else {
                Part::Side {
                    azimuth: normal.y.atan2(normal.x),
                }
            };
            SurfacePoint {
                offset: normal * radius,
                normal,
                tangents: [t, normal.cross(&t)],
                area,
                part,
            }
        })
        .collect()
}

fn cylinder_surface(radius: f64, height: f64) -> Vec<SurfacePoint> {
    let mut points = Vec::new();
    let side_area = TAU * radius * height / (RING_SAMPLES * HEIGHT_SAMPLES) as f64;
    for k in 0..RING_SAMPLES {
        let phi = TAU * (k as f64 + 0.5) / RING_SAMPLES as f64;
        let normal = Vector3::new(phi.cos(), phi.sin(), 0.0);
        for h in 0..HEIGHT_SAMPLES {
            let z = height * ((h as f64 + 0.5) / HEIGHT_SAMPLES as f64 - 0.5);
            points.push(side_point(
                normal * radius + Vector3::z() * z,
                normal,
                side_area,
            ));
        }
    }
    // Concentric rings of 6, 12, 18 ... points, each covering an equal area.
    let count: usize = (1..=DISC_RINGS).map(|k| 6 * k).sum();
    let area = PI * radius * radius / count as f64;
    for ring in 1..=DISC_RINGS {
        let r = radius * (ring as f64 - 0.5) / DISC_RINGS as f64;
        for k in 0..6 * ring {
            let phi = TAU * k as f64 / (6 * ring) as f64;
            let offset = Vector3::new(r * phi.cos(), r * phi.sin(), 0.5 * height);
            points.push(top_point(offset, area));
        }
    }
    points
}

fn cuboid_surface(size: [f64; 3]) -> Vec<SurfacePoint> {
    let half = size.map(|s| 0.5 * s);
    let grid = |k: usize| (k as f64 + 0.5) / FACE_SAMPLES as f64 * 2.0 - 1.0;
    let per_face = (FACE_SAMPLES * FACE_SAMPLES) as f64;
    let mut points = Vec::new();
    // The four vertical faces: normal along +-x or +-y.
    for (axis, sign) in [(0, 1.0), (1, 1.0), (0, -1.0), (1, -1.0)] {
        let other = 1 - axis;
        let mut normal = Vector3::zeros();
        normal[axis] = sign;
        let area = size[other] * size[2] / per_face;
        for a in 0..FACE_SAMPLES {
            for b in 0..FACE_SAMPLES {
                let mut offset = Vector3::zeros();
                offset[axis] = sign * half[axis];
                offset[other] = grid(a) * half[other];
                offset.z = grid(b) * half[2];
                points.push(side_point(offset, normal, area));
            }
        }
    }
    let area = size[0] * size[1] / per_face;
    for a in 0..FACE_SAMPLES {
        for b in 0..FACE_SAMPLES {
            let offset = Vector3::new(grid(a) * half[0], grid(b) * half[1], half[2]);
            points.push(top_point(offset, area));
        }
    }
    points
}
