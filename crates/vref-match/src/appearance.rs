use vref_scene::SceneGraph;

use crate::MatchError;

/// Cosine similarity of every human feature with every robot feature
/// (ALGORITHMS.md Eq. 1), row-major `n x m`. A pair where either graph has
/// no features, or either feature has zero norm, gets 1: no information.
pub fn appearance_affinity(human: &SceneGraph, robot: &SceneGraph) -> Result<Vec<f64>, MatchError> {
    let (dh, dr) = (human.feature_dim(), robot.feature_dim());
    let (n, m) = (human.len(), robot.len());
    if dh == 0 || dr == 0 {
        return Ok(vec![1.0; n * m]);
    }
    if dh != dr {
        return Err(MatchError::FeatureDimsDiffer {
            human: dh,
            robot: dr,
        });
    }
    let norms =
        |g: &SceneGraph| -> Vec<f64> { g.objects().iter().map(|o| norm(&o.feature)).collect() };
    let (hn, rn) = (norms(human), norms(robot));
    let mut a = Vec::with_capacity(n * m);
    for (h, &nh) in human.objects().iter().zip(&hn) {
        for (r, &nr) in robot.objects().iter().zip(&rn) {
            a.push(if nh == 0.0 || nr == 0.0 {
                1.0
            } else {
                dot(&h.feature, &r.feature) / (nh * nr)
            });
        }
    }
    Ok(a)
}

/// The dot product of two features, summed in order in f64 (the engine's
/// rows sum side by side to these bits: `engine/dots.rs`).
pub(crate) fn dot(u: &[f32], v: &[f32]) -> f64 {
    u.iter()
        .zip(v)
        .map(|(&a, &b)| f64::from(a) * f64::from(b))
        .sum()
}

pub(crate) fn norm(u: &[f32]) -> f64 {
    dot(u, u).sqrt()
}
