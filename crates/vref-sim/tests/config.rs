#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! Configurations: presets are valid and serialisable, bad values are
//! refused by name.

use vref_sim::{ConfigError, Generator, Preset, Shape, SimConfig};

fn field_of(error: ConfigError) -> String {
    match error {
        ConfigError::Invalid { field, .. } => field,
        other => panic!("expected an invalid field, got {other}"),
    }
}

#[test]
fn presets_are_valid_and_survive_a_json_round_trip() {
    for preset in Preset::ALL {
        let config = preset.config();
        config.validate().unwrap();
        let json = serde_json::to_string(&config).unwrap();
        let back: SimConfig = serde_json::from_str(&json).unwrap();
        assert_eq!(back, config, "{preset}");
        assert_eq!(preset.name().parse::<Preset>().unwrap(), preset);
    }
}

#[test]
fn unknown_fields_are_refused() {
    let mut json = serde_json::to_value(Preset::Moi.config()).unwrap();
    json["robot"]["noise"]["depht"] = serde_json::json!(0.1);
    let error = serde_json::from_value::<SimConfig>(json).unwrap_err();
    assert!(error.to_string().contains("depht"), "{error}");

    let mut json = serde_json::to_value(Preset::Moi.config()).unwrap();
    json["classes"][0]["shape"] = serde_json::json!({"kind": "sphere", "radius": 0.1, "height": 1});
    assert!(serde_json::from_value::<SimConfig>(json).is_err());
}

#[test]
fn shapes_are_written_with_their_kind() {
    let json = serde_json::to_value(Shape::Cylinder {
        radius: 0.1,
        height: 0.2,
    })
    .unwrap();
    assert_eq!(
        json,
        serde_json::json!({"kind": "cylinder", "radius": 0.1, "height": 0.2})
    );
}

/// A change that makes a valid configuration invalid.
type Breakage = fn(&mut SimConfig);

#[test]
fn invalid_values_are_refused_naming_the_field() {
    let cases: Vec<(&str, Breakage)> = vec![
        ("classes[0].instances", |c| c.classes[0].instances = [3, 1]),
        ("human.hfov_deg", |c| c.human.hfov_deg = 180.0),
        ("robot.noise.depth", |c| c.robot.noise.depth = -0.1),
        ("robot.depth_range", |c| c.robot.depth_range = [2.0, 1.0]),
        ("workspace.area[1]", |c| c.workspace.area[1] = f64::NAN),
        ("classes[2].sides[0].patches[0].rgb[1]", |c| {
            c.classes[2].sides[0].patches[0].rgb[1] = 1.5
        }),
        ("classes[1].shape.radius", |c| {
            c.classes[1].shape = Shape::Sphere { radius: 0.0 }
        }),
        ("classes[0].shape", |c| {
            c.classes[0].shape = Shape::Sphere { radius: 5.0 }
        }),
        ("classes", |c| {
            c.classes.iter_mut().for_each(|k| k.instances = [0, 0])
        }),
        ("features.value_levels", |c| c.features.value_levels = 0),
        ("min_objects_per_view", |c| c.min_objects_per_view = 0),
    ];
    for (field, break_it) in cases {
        let mut config = Preset::Moi.config();
        break_it(&mut config);
        let error = config.validate().unwrap_err();
        assert!(!error.to_string().is_empty());
        assert_eq!(field_of(error.clone()), field);
        // The generator refuses it too, before drawing anything.
        assert_eq!(Generator::new(config, 0).unwrap_err(), error);
    }
}

#[test]
fn unknown_presets_are_refused_listing_the_known_ones() {
    let error = "kitchen".parse::<Preset>().unwrap_err();
    assert_eq!(error, ConfigError::UnknownPreset("kitchen".to_owned()));
    assert!(error.to_string().contains("moi, mrc"));
}

#[test]
fn noiseless_zeroes_every_sensor_error_and_nothing_else() {
    let config = Preset::Mrc.config();
    let quiet = config.clone().noiseless();
    for camera in [quiet.robot, quiet.human] {
        let n = camera.noise;
        let knobs = [
            n.depth,
            n.depth_scale,
            n.surface_bias,
            n.segmentation,
            n.pixel,
            n.white_balance,
            n.exposure,
        ];
        assert!(knobs.iter().all(|&k| k == 0.0));
    }
    let mut restored = quiet;
    restored.robot.noise = config.robot.noise;
    restored.human.noise = config.human.noise;
    assert_eq!(restored, config);
}
