#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! What the matchers make of generated scenes: perfect when nothing is
//! ambiguous and nothing errs, worse as depth error grows.

use vref_match::{Evaluation, Method, Params, Tier};
use vref_scene::{Limits, SceneGraph, ScenePair};
use vref_sim::{Generator, Preset, SimConfig};

/// The pair without the human objects that have no partner: accuracy
/// counts those wrong whenever the robot view is at least as large, which
/// no method can avoid, so perfection is only defined on the rest.
fn partnered_only(pair: &ScenePair) -> ScenePair {
    let objects = pair
        .human
        .objects()
        .iter()
        .filter(|o| pair.ground_truth.iter().any(|&(h, _)| h == o.id))
        .cloned()
        .collect();
    let human = SceneGraph::new(objects, None, &Limits::default()).unwrap();
    ScenePair::new(
        pair.name.clone(),
        pair.robot.clone(),
        human,
        pair.ground_truth.clone(),
    )
    .unwrap()
}

fn accuracies(pairs: &[ScenePair], beta: f64) -> Vec<(Method, f64)> {
    let params = Params {
        beta,
        ..Params::default()
    };
    let mut evaluation = Evaluation::new(&Method::ALL, params).unwrap();
    for pair in pairs {
        evaluation.add(pair).unwrap();
    }
    evaluation
        .reports()
        .iter()
        .map(|r| (r.method, r.summary.accuracy.mean))
        .collect()
}

#[test]
fn every_method_is_perfect_on_noiseless_scenes_of_distinct_objects() {
    let mut config = Preset::Moi.config().noiseless();
    for class in &mut config.classes {
        class.instances = [1, 1];
    }
    let mut pairs = Vec::new();
    for seed in [31, 32] {
        let generator = Generator::new(config.clone(), seed).unwrap();
        for scene in generator.scenes(15) {
            let pair = partnered_only(&scene.unwrap().pair);
            if pair.human.len() >= 3 {
                pairs.push(pair);
            }
        }
    }
    assert!(pairs.len() >= 25, "only {} usable scenes", pairs.len());
    // Without noise the true distances agree exactly, while a wrong
    // assignment on a table top often gets within a few centimetres: a
    // 1 cm bandwidth (beta = 1e-4 m^2) is the scale that separates them.
    for (method, accuracy) in accuracies(&pairs, 1e-4) {
        assert_eq!(accuracy, 1.0, "{method}");
    }
}

fn with_depth_noise(factor: f64) -> SimConfig {
    let mut config = Preset::Moi.config();
    config.robot.noise.depth *= factor;
    config.human.noise.depth *= factor;
    config
}

#[test]
fn rrwm_accuracy_falls_as_depth_error_grows() {
    let factors = [0.0, 0.5, 1.0, 2.0, 4.0];
    let mut curve = Vec::new();
    for factor in factors {
        let generator = Generator::new(with_depth_noise(factor), 77).unwrap();
        let pairs: Vec<_> = generator.scenes(30).map(|s| s.unwrap().pair).collect();
        let params = Params::default();
        let mut evaluation = Evaluation::new(&[Method::Rrwm], params).unwrap();
        for pair in &pairs {
            evaluation.add(pair).unwrap();
        }
        curve.push(evaluation.reports()[0].summary.accuracy.mean);
    }
    // Same scenes at every level (the noise draws are shared), so the
    // curve is smooth; allow a little non-monotonic wobble.
    for (k, pair) in curve.windows(2).enumerate() {
        assert!(
            pair[1] <= pair[0] + 0.03,
            "accuracy rose from {:.3} to {:.3} between depth factors {} and {}: {curve:?}",
            pair[0],
            pair[1],
            factors[k],
            factors[k + 1]
        );
    }
    assert!(
        curve[0] - curve[4] > 0.25,
        "depth error barely matters: {curve:?}"
    );
}

#[test]
fn the_live_tier_is_no_less_accurate_than_the_exact_tier() {
    for preset in [Preset::Moi, Preset::Mrc] {
        // 30 scenes, as the target: on 20 scenes of this seed mrc
        // is 0.014 below, within the set-to-set spread.
        let generator = Generator::new(preset.config(), 404).unwrap();
        let pairs: Vec<_> = generator.scenes(30).map(|s| s.unwrap().pair).collect();
        let accuracy = |tier: Tier| {
            let mut evaluation = Evaluation::new(&[Method::Paper], Params::default())
                .unwrap()
                .with_tier(tier);
            for pair in &pairs {
                evaluation.add(pair).unwrap();
            }
            evaluation.reports()[0].summary.accuracy.mean
        };
        let (exact, live) = (accuracy(Tier::Exact), accuracy(Tier::Live));
        // Measured on the README's 30-scene sets: live is 0.03 to 0.10
        // above exact (pruning by appearance gates the spatial term).
        assert!(
            live >= exact - 0.01,
            "{preset:?}: live {live:.3}, exact {exact:.3}"
        );
    }
}
