use vref_scene::SceneGraph;
use vref_wire::Ray;

/// The object of `graph` a ray points at: the smallest angle between the
/// ray and the direction from its origin to the object, if within the
/// ray's cone. Objects behind the origin (angle > 90 degrees) never count.
pub fn resolve_ray(graph: &SceneGraph, ray: &Ray) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (k, object) in graph.objects().iter().enumerate() {
        let to_object = object.position - ray.origin;
        let distance = to_object.norm();
        if distance == 0.0 {
            continue;
        }
        let cosine = (to_object.dot(&ray.direction) / distance).clamp(-1.0, 1.0);
        let angle = cosine.acos();
        if angle <= ray.cone_half_angle && best.is_none_or(|(_, a)| angle < a) {
            best = Some((k, angle));
        }
    }
    best.map(|(k, _)| k)
}
