#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::graph;
use vref_match::{MatchError, appearance_affinity};
use vref_scene::SceneObject;

fn objects(features: &[&[f32]]) -> Vec<SceneObject> {
    features
        .iter()
        .enumerate()
        .map(|(k, f)| SceneObject::new(k as u64, [k as f64, 0.0, 0.0], f.to_vec()))
        .collect()
}

#[test]
fn cosine_similarity_of_every_pair() {
    let h = graph(objects(&[&[1.0, 0.0], &[1.0, 1.0]]));
    let r = graph(objects(&[&[2.0, 0.0], &[0.0, 3.0], &[-1.0, 0.0]]));
    let a = appearance_affinity(&h, &r).unwrap();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let expected = [1.0, 0.0, -1.0, s, s, -s];
    for (got, want) in a.iter().zip(expected) {
        assert!((got - want).abs() < 1e-12, "{a:?}");
    }
}

#[test]
fn no_features_or_zero_norm_means_no_information() {
    let h = graph(objects(&[&[], &[]]));
    let r = graph(objects(&[&[]]));
    assert_eq!(appearance_affinity(&h, &r).unwrap(), vec![1.0, 1.0]);

    let h = graph(objects(&[&[0.0, 0.0], &[1.0, 0.0]]));
    let r = graph(objects(&[&[0.0, 2.0]]));
    assert_eq!(appearance_affinity(&h, &r).unwrap(), vec![1.0, 0.0]);
}

#[test]
fn features_of_different_dimension_are_an_error() {
    let h = graph(objects(&[&[1.0, 0.0]]));
    let r = graph(objects(&[&[1.0, 0.0, 0.0]]));
    assert_eq!(
        appearance_affinity(&h, &r),
        Err(MatchError::FeatureDimsDiffer { human: 2, robot: 3 })
    );
}
