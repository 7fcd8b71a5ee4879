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
    /// `w = exp(-angle^2 / 2 s^2) / s^2` (the density of the angle in the
    /// plane across the ray), where `s^2` is the pointing error's
    /// variance (`sigma`, a third of the cone half-angle, squared) plus
    /// the angle the object's own stated position error subtends across
    /// the line of sight. 1 when no other object is in the cone.
    pub share: f64,
}

/// The object of `graph` a ray points at: the most likely one by
/// [`Pointed::share`]'s weights (the smallest angle when no object states
/// a position error) among those within the ray's cone (widened for an
/// object by its own error), with its share.
///
/// The person aims at where the object is; the headset's view has it
/// where it was measured, off by the error it states. Without that error
/// in the weights, a neighbour measured nearer the ray took the answer
/// with a share of 0.95 in the synthetic demo (2 degrees of pointing
/// error, a few centimetres of the headset's depth error at a metre).
/// Objects behind the origin (angle > 90 degrees) never count. Allocates
/// nothing: this runs on the query path.
pub fn resolve_ray(graph: &SceneGraph, ray: &Ray) -> Option<Pointed> {
    let sigma = ray.cone_half_angle / CONE_SIGMAS;
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
        let across = across_variance(&object.position_sigma, &(to_object / distance));
        let s2 = sigma * sigma + across / (distance * distance);
        // The cone holds CONE_SIGMAS of the pointing error; an object's
        // own error widens it alike, or the object meant, measured just
        // outside, would leave its share to a neighbour.
        if angle > ray.cone_half_angle.max(CONE_SIGMAS * s2.sqrt()) {
            continue;
        }
        let weight = (-0.5 * angle * angle / s2).exp() / s2;
        total += weight;
        if best.is_none_or(|(_, w)| weight > w) {
            best = Some((k, weight));
        }
    }
    // `total` holds the best's own weight, positive inside the cone.
    best.map(|(row, weight)| Pointed {
        row,
        share: weight / total,
    })
}

/// The variance, per axis across the line of sight `u` (a unit vector),
/// of a position whose axes err independently by `sigma`: half of what
/// the covariance holds off `u`.
fn across_variance(sigma: &[f64; 3], u: &nalgebra::Vector3<f64>) -> f64 {
    let var = sigma.map(|s| s * s);
    let trace = var[0] + var[1] + var[2];
    let along = var[0] * u.x * u.x + var[1] * u.y * u.y + var[2] * u.z * u.z;
    0.5 * (trace - along).max(0.0)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use nalgebra::{Point3, Vector3};
    use vref_scene::{Limits, SceneObject};

    fn graph(points: &[[f64; 3]]) -> SceneGraph {
        graph_with_sigma(points, 0.0)
    }

    fn graph_with_sigma(points: &[[f64; 3]], sigma: f64) -> SceneGraph {
        let objects = points
            .iter()
            .enumerate()
            .map(|(k, p)| SceneObject {
                id: k as u64 + 1,
                position: Point3::from(*p),
                feature: Vec::new(),
                position_sigma: [sigma; 3],
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

    /// The share is a probability: among rays whose best object has a
    /// share of at least 0.9, at least 0.9 name the object aimed at, when
    /// the positions are measured with the error they state. Six objects
    /// 8 cm apart at a metre, measured 2.5 cm off per axis; 2 degrees of
    /// pointing error in a cone of 6 degrees. The same rays over the same
    /// positions weighed without their stated error are right less often
    /// than their shares say (0.84 of 6409; checked too: the test can fail).
    #[test]
    fn shares_over_positions_measured_with_their_stated_error_are_calibrated() {
        // SplitMix64 and Box-Muller: no random crate for one test.
        let mut state = 3u64;
        let mut uniform = move || {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut normal = |s: f64| -> f64 {
            let (u, v) = (uniform(), uniform());
            s * (-2.0 * (1.0 - u).ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        };
        let truth: Vec<[f64; 3]> = (0..6).map(|k| [0.08 * k as f64 - 0.2, 0.0, 1.0]).collect();
        let (sigma_position, sigma_ray) = (0.025, 2f64.to_radians());
        // (confident, right) with the stated error, and without it.
        let mut counts = [(0usize, 0usize); 2];
        for trial in 0..20000 {
            let measured: Vec<[f64; 3]> = truth
                .iter()
                .map(|p| p.map(|c| c + normal(sigma_position)))
                .collect();
            let target = trial % truth.len();
            let aim = Vector3::from(truth[target]).normalize();
            let off = Vector3::new(normal(sigma_ray), normal(sigma_ray), 0.0);
            let mut ray = ray_along_z(3.0 * sigma_ray);
            ray.direction = nalgebra::Unit::new_normalize(aim + off);
            for (count, stated) in counts.iter_mut().zip([sigma_position, 0.0]) {
                let g = graph_with_sigma(&measured, stated);
                if let Some(p) = resolve_ray(&g, &ray).filter(|p| p.share >= 0.9) {
                    count.0 += 1;
                    count.1 += usize::from(p.row == target);
                }
            }
        }
        let rate = |(confident, right): (usize, usize)| right as f64 / confident as f64;
        let [stated, bare] = counts;
        assert!(stated.0 > 500, "too few confident rays: {stated:?}");
        assert!(rate(stated) >= 0.9, "with the stated error: {stated:?}");
        assert!(rate(bare) < 0.9, "without it: {bare:?}");
        eprintln!("with the stated error {stated:?}, without {bare:?}");
    }

    #[test]
    fn a_stated_position_error_lowers_the_share_of_a_near_miss() {
        let points = [[0.0, 0.0, 1.0], [0.05f64.tan(), 0.0, 1.0]];
        let bare = resolve_ray(&graph(&points), &ray_along_z(0.1)).unwrap();
        let noisy = resolve_ray(&graph_with_sigma(&points, 0.03), &ray_along_z(0.1)).unwrap();
        assert_eq!((bare.row, noisy.row), (0, 0));
        assert!(noisy.share < bare.share, "{noisy:?} {bare:?}");
    }

    #[test]
    fn nothing_in_the_cone_is_none() {
        let g = graph(&[[1.0, 0.0, 1.0], [0.0, 0.0, -1.0]]);
        assert_eq!(resolve_ray(&g, &ray_along_z(0.1)), None);
    }
}
