#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! Noise sweeps: which knobs they scale, what they refuse, and that depth
//! error costs accuracy.

use vref_match::{Method, Params};
use vref_scene::ScenePair;
use vref_sim::{
    Generator, NoiseSweep, Preset, SensorNoise, SimConfig, Sweep, SweepError, accuracy_curves,
};

fn sweep(noise: NoiseSweep, levels: &[f64], count: u64) -> Sweep {
    Sweep {
        noise,
        base: Preset::Moi.config(),
        name: "moi".to_owned(),
        levels: levels.to_vec(),
        count,
        seed: 77,
        methods: Method::ALL.to_vec(),
        params: Params::default(),
    }
}

fn pairs(config: SimConfig, count: u64) -> Vec<ScenePair> {
    Generator::new(config, 5)
        .unwrap()
        .scenes(count)
        .map(|s| s.unwrap().pair)
        .collect()
}

/// Every knob of `noise` as a list, to compare families of knobs.
fn knobs(n: &SensorNoise) -> [f64; 7] {
    [
        n.depth,
        n.depth_scale,
        n.surface_bias,
        n.segmentation,
        n.pixel,
        n.white_balance,
        n.exposure,
    ]
}

#[test]
fn each_sweep_scales_its_own_knobs_in_both_cameras_and_nothing_else() {
    let base = Preset::Mrc.config();
    // Indices into `knobs`: depth, depth_scale / pixel, white_balance, exposure.
    for (noise, scaled) in [
        (NoiseSweep::Depth, vec![0, 1]),
        (NoiseSweep::Feature, vec![4, 5, 6]),
    ] {
        let config = noise.scaled(&base, 3.0);
        for (before, after) in [
            (&base.robot.noise, &config.robot.noise),
            (&base.human.noise, &config.human.noise),
        ] {
            let (before, after) = (knobs(before), knobs(after));
            for k in 0..before.len() {
                let expected = if scaled.contains(&k) {
                    3.0 * before[k]
                } else {
                    before[k]
                };
                assert_eq!(after[k], expected, "{noise}, knob {k}");
            }
        }
        let mut rest = config.clone();
        rest.robot.noise = base.robot.noise;
        rest.human.noise = base.human.noise;
        assert_eq!(rest, base, "{noise} changed more than the noise");
    }
}

#[test]
fn feature_noise_leaves_positions_alone_and_depth_noise_leaves_features_alone() {
    let base = Preset::Moi.config();
    let quiet = pairs(NoiseSweep::Feature.scaled(&base, 0.0), 4);
    let loud = pairs(NoiseSweep::Feature.scaled(&base, 4.0), 4);
    let mut features_differ = false;
    for (a, b) in quiet.iter().zip(&loud) {
        for (x, y) in a.human.objects().iter().zip(b.human.objects()) {
            assert_eq!(x.id, y.id);
            assert_eq!(x.position, y.position);
            features_differ |= x.feature != y.feature;
        }
    }
    assert!(features_differ, "feature noise changed no feature");

    let quiet = pairs(NoiseSweep::Depth.scaled(&base, 0.0), 4);
    let loud = pairs(NoiseSweep::Depth.scaled(&base, 4.0), 4);
    let mut positions_differ = false;
    for (a, b) in quiet.iter().zip(&loud) {
        assert_eq!(a.ground_truth, b.ground_truth);
        for (x, y) in a.robot.objects().iter().zip(b.robot.objects()) {
            assert_eq!(x.feature, y.feature);
            positions_differ |= x.position != y.position;
        }
    }
    assert!(positions_differ, "depth noise moved no object");
}

#[test]
fn a_sweep_gives_one_point_per_method_and_level_and_depth_error_costs_rrwm() {
    let levels = [0.0, 1.0, 4.0];
    let plan = sweep(NoiseSweep::Depth, &levels, 8);
    let mut evaluated = 0;
    let points = plan.run_with(|| evaluated += 1).unwrap();
    assert_eq!(evaluated, 24);
    assert_eq!(plan.total_scenes(), 24);
    assert_eq!(points.len(), levels.len() * Method::ALL.len());
    for (k, p) in points.iter().enumerate() {
        assert_eq!(p.level, levels[k / Method::ALL.len()]);
        assert_eq!(p.method, Method::ALL[k % Method::ALL.len()]);
        assert_eq!(p.summary.scenes, 8);
        assert!((0.0..=1.0).contains(&p.summary.accuracy.mean));
    }

    let curves = accuracy_curves(&points);
    assert_eq!(
        curves.iter().map(|(m, _)| *m).collect::<Vec<_>>(),
        Method::ALL
    );
    let (_, rrwm) = curves.iter().find(|(m, _)| *m == Method::Rrwm).unwrap();
    let xs: Vec<f64> = rrwm.iter().map(|p| p.0).collect();
    assert_eq!(xs, levels);
    let (lowest, highest) = (rrwm[0].1, rrwm[2].1);
    assert!(
        highest < lowest - 0.1,
        "rrwm accuracy {lowest:.3} without depth error, {highest:.3} at 4x: {rrwm:?}"
    );
}

#[test]
fn bad_plans_are_refused_before_any_scene_is_generated() {
    let refused = |plan: Sweep| {
        let mut called = false;
        let error = plan.run_with(|| called = true).unwrap_err();
        assert!(!called, "{error}");
        error
    };
    assert_eq!(
        refused(sweep(NoiseSweep::Depth, &[], 2)),
        SweepError::NoLevels
    );
    for bad in [-0.5, f64::NAN, f64::INFINITY] {
        let error = refused(sweep(NoiseSweep::Depth, &[0.0, 1.0, bad], 2));
        assert!(
            matches!(error, SweepError::BadLevel { index: 2, .. }),
            "{error}"
        );
    }
    assert_eq!(
        refused(sweep(NoiseSweep::Feature, &[1.0], 0)),
        SweepError::NoScenes
    );
    let mut plan = sweep(NoiseSweep::Feature, &[1.0], 2);
    plan.methods.clear();
    assert_eq!(refused(plan), SweepError::NoMethods);
    let mut plan = sweep(NoiseSweep::Feature, &[1.0], 2);
    plan.params.beta = -1.0;
    assert!(matches!(refused(plan), SweepError::Params(_)));
    let mut plan = sweep(NoiseSweep::Feature, &[1.0], 2);
    plan.base.attempts = 0;
    assert!(matches!(
        refused(plan),
        SweepError::Config { level: 1.0, .. }
    ));
}

#[test]
fn sweep_names_parse_back_and_unknown_ones_list_the_known() {
    for noise in NoiseSweep::ALL {
        assert_eq!(noise.name().parse::<NoiseSweep>().unwrap(), noise);
    }
    let error = "depth".parse::<NoiseSweep>().unwrap_err();
    let message = error.to_string();
    assert!(
        message.contains("\"depth\"") && message.contains("depth-noise, feature-noise"),
        "{message}"
    );
}
