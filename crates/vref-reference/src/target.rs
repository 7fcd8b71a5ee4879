use vref_scene::SceneGraph;
use vref_wire::Ray;

/// The cone half-angle holds this many standard deviations of the
/// pointing error: it is the recogniser's bound on where the target can
/// be, not the error's spread.
const CONE_SIGMAS: f64 = 3.0;

/// The object a ray points at and how sure the pointing alone is of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pointed {
    /// Its row in the human view.
    pub row: usize,
    /// The probability that the person meant it rather than another
    /// object in the cone: `w / sum(w)` over the objects in the cone, with
    /// `w = exp(-angle^2 / 2 sigma^2)` and `sigma` a third of the cone
    /// half-angle. 1 when no other object is in the cone.
    pub share: f64,
}

/// The object of `graph` a ray points at: the smallest angle between the
/// ray and the direction from its origin to the object, if within the
/// ray's cone, with its pointing share among the objects in the cone.
/// Objects behind the origin (angle > 90 degrees) never count. Allocates
/// nothing: this runs on the query path.
pub fn resolve_ray(graph: &SceneGraph, ray: &Ray) -> Option<Pointed> {
    let sigma = ray.cone_half_angle / CONE_SIGMAS;
    let weight = |angle: f64| (-0.5 * (angle / sigma).powi(2)).exp();
    let mut best: Option<(usize, f64)> = None;
    let mut total = 0.0;
    for (k, object) in graph.objects().iter().enumerate() {
        let to_object = object.position - ray.origin;
        let distance = to_object.norm();
        if distance == 0.0 {
            continue;
        }
        let cosine = (to_object.dot(&ray.direction) / distance).clamp(-1.0, 1.0);
        let angle = cosine.acos();
        if angle > ray.cone_half_angle {
            continue;
        }
        total += weight(angle);
        if best.is_none_or(|(_, a)| angle < a) {
            best = Some((k, angle));
        }
    }
    // `total` holds the best's own weight, at least exp(-4.5) inside the
    // cone: never zero.
    best.map(|(row, angle)| Pointed {
        row,
        share: weight(angle) / total,
    })
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use nalgebra::{Point3, Vector3};
    use vref_scene::{Limits, SceneObject};

    fn graph(points: &[[f64; 3]]) -> SceneGraph {
        let objects = points
            .iter()
            .enumerate()
            .map(|(k, p)| SceneObject {
                id: k as u64 + 1,
                position: Point3::from(*p),
                feature: Vec::new(),
                position_sigma: [0.0; 3],
            })
            .collect();
        SceneGraph::new(objects, None, &Limits::default()).unwrap()
    }

    fn ray_along_z(cone: f64) -> Ray {
        Ray {
            session: 0,
            sequence: 0,
            timestamp_ns: 0,
            origin: Point3::origin(),
            direction: Vector3::z_axis(),
            cone_half_angle: cone,
            confidence: 1.0,
        }
    }

    #[test]
    fn a_lone_object_in_the_cone_takes_the_whole_share() {
        let g = graph(&[[0.01, 0.0, 1.0], [1.0, 0.0, 1.0]]);
        let p = resolve_ray(&g, &ray_along_z(0.1)).unwrap();
        assert_eq!(p, Pointed { row: 0, share: 1.0 });
    }

    #[test]
    fn two_objects_at_the_same_angle_split_it() {
        let g = graph(&[[0.03, 0.0, 1.0], [-0.03, 0.0, 1.0]]);
        let p = resolve_ray(&g, &ray_along_z(0.1)).unwrap();
        assert!((p.share - 0.5).abs() < 1e-9, "{p:?}");
    }

    #[test]
    fn a_neighbour_at_the_cone_edge_takes_little() {
        // On the ray, and one at 0.09 rad of the 0.1 rad cone: 2.7 sigma.
        let g = graph(&[[0.0, 0.0, 1.0], [0.09f64.tan(), 0.0, 1.0]]);
        let p = resolve_ray(&g, &ray_along_z(0.1)).unwrap();
        let w = (-0.5f64 * 2.7 * 2.7).exp();
        assert_eq!(p.row, 0);
        assert!((p.share - 1.0 / (1.0 + w)).abs() < 1e-9, "{p:?}");
        assert!(p.share > 0.97);
    }

    #[test]
    fn nothing_in_the_cone_is_none() {
        let g = graph(&[[1.0, 0.0, 1.0], [0.0, 0.0, -1.0]]);
        assert_eq!(resolve_ray(&g, &ray_along_z(0.1)), None);
    }
}
