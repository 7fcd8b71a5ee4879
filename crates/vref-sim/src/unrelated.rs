//! Views with nothing in common, for checking that a matcher does not
//! find a motion where there is none: any partner it gives is wrong.
//!
//! - [`across_scenes`]: the human view of one scene against the robot view
//!   of another of the same family (same kinds of objects, same layout
//!   rules, look-alikes on both sides).
//! - [`shuffled`]: one scene's human view with every coordinate of every
//!   position taken from a different object (x of one, y of another, z of
//!   a third): the same objects and appearance in the same region, with no
//!   rigid relation to the robot view.
//! - [`random_clouds`]: two independent uniform clouds of objects with
//!   random histogram features in front of their cameras.
//!
//! Every result has an empty ground truth.

use rand::Rng;
use rand::seq::SliceRandom;
use vref_scene::{Limits, PairError, SceneGraph, SceneObject, ScenePair};

use crate::random::{Purpose, keyed};

fn graph(objects: Vec<SceneObject>) -> Result<SceneGraph, PairError> {
    SceneGraph::new(objects, None, &Limits::default())
        .map_err(ScenePair::graph_error(vref_scene::Side::Human))
}

/// Scene `k`'s human view against scene `k + 1`'s robot view (cyclically).
pub fn across_scenes(pairs: &[ScenePair]) -> Result<Vec<ScenePair>, PairError> {
    (0..pairs.len())
        .filter(|_| pairs.len() >= 2)
        .map(|k| {
            let other = &pairs[(k + 1) % pairs.len()];
            ScenePair::new(
                format!("{}+{}", pairs[k].name, other.name),
                other.robot.clone(),
                pairs[k].human.clone(),
                Vec::new(),
            )
        })
        .collect()
}

/// Each scene's human positions with their coordinates shuffled across
/// objects, independently per axis (`seed` picks the shuffles).
pub fn shuffled(pairs: &[ScenePair], seed: u64) -> Result<Vec<ScenePair>, PairError> {
    pairs
        .iter()
        .enumerate()
        .map(|(k, pair)| {
            let mut rng = keyed(seed, Purpose::Unrelated, 0, k as u64);
            let objects = pair.human.objects();
            let mut axes: Vec<Vec<f64>> = (0..3)
                .map(|a| objects.iter().map(|o| o.position[a]).collect())
                .collect();
            for axis in &mut axes {
                axis.shuffle(&mut rng);
            }
            let moved = objects
                .iter()
                .enumerate()
                .map(|(i, o)| {
                    let mut o = o.clone();
                    o.position = [axes[0][i], axes[1][i], axes[2][i]].into();
                    o
                })
                .collect();
            ScenePair::new(
                format!("{}-shuffled", pair.name),
                pair.robot.clone(),
                graph(moved)?,
                Vec::new(),
            )
        })
        .collect()
}

/// `count` pairs of independent clouds of `objects` objects each, uniform
/// in a box 0.6-1.6 m in front of each camera, with random non-negative
/// features of `dims` values (histogram-like: cosines between them are
/// high, as between real histograms).
pub fn random_clouds(
    count: usize,
    objects: usize,
    dims: usize,
    seed: u64,
) -> Result<Vec<ScenePair>, PairError> {
    (0..count)
        .map(|k| {
            let mut rng = keyed(seed, Purpose::Unrelated, objects as u64, k as u64);
            let mut view = |first_id: u64| {
                let objects = (0..objects)
                    .map(|i| {
                        let position = [
                            rng.random_range(-0.5..0.5),
                            rng.random_range(-0.4..0.4),
                            rng.random_range(0.6..1.6),
                        ];
                        let feature = (0..dims).map(|_| rng.random::<f32>()).collect();
                        SceneObject::new(first_id + i as u64, position, feature)
                    })
                    .collect();
                graph(objects)
            };
            let robot = view(1000)?;
            let human = view(1)?;
            ScenePair::new(format!("cloud-{objects}-{k}"), robot, human, Vec::new())
        })
        .collect()
}
