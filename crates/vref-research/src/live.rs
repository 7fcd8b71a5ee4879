//! The synthetic feeds' live world as the examples measure it.

use vref_scene::{GraphError, Limits, SceneGraph, Side};
use vref_sim::LiveWorld;

/// `side`'s view of `world` at `t` (frame `frame`, which keys its
/// measurement errors) as a scene graph, carrying its camera's up vector
/// where `up` (as the synthetic feeds publish it, `[feeds] up_vectors`).
pub fn view_graph(
    world: &LiveWorld,
    side: Side,
    t: f64,
    frame: u64,
    limits: &Limits,
    up: bool,
) -> Result<SceneGraph, GraphError> {
    let view = world.observe(side, t, frame);
    let graph = view.graph(limits)?;
    if !up {
        return Ok(graph);
    }
    let u = view.camera.direction_to_camera(&nalgebra::Vector3::z());
    graph.with_up(Some([u.x, u.y, u.z]))
}
