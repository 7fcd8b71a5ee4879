#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use vref_config::{Config, ConfigError, Source};

fn shipped() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../config/vref.toml")
}

#[test]
fn shipped_file_holds_exactly_the_built_in_defaults() {
    assert_eq!(Config::from_file(&shipped()).unwrap(), Config::default());
}

#[test]
fn partial_file_keeps_defaults_for_the_rest() {
    let c = Config::parse("[matching]\nbeta = 2500.0\n", Path::new("x.toml")).unwrap();
    assert_eq!(c.matching.beta, 2500.0);
    assert_eq!(c.matching.rrwm, Config::default().matching.rrwm);
}

#[test]
fn unknown_keys_are_errors_naming_the_key() {
    for text in [
        "[matching]\nbetta = 1.0\n",
        "[scene]\ncapacty = 3\n",
        "[matching.sm]\ntoll = 1.0\n",
        "[extra]\n",
    ] {
        match Config::parse(text, Path::new("x.toml")) {
            Err(ConfigError::Parse { message, .. }) => {
                let key = text
                    .lines()
                    .last()
                    .unwrap()
                    .split([' ', '[', ']'])
                    .find(|s| !s.is_empty())
                    .unwrap();
                assert!(message.contains(key), "{message} should name {key}");
            }
            other => panic!("{text:?}: {other:?}"),
        }
    }
}

/// The error and its causes, as a program would print them.
fn chain(err: &dyn std::error::Error) -> String {
    let mut text = err.to_string();
    let mut source = err.source();
    while let Some(e) = source {
        text = format!("{text}: {e}");
        source = e.source();
    }
    text
}

#[test]
fn bad_values_are_errors_naming_the_parameter() {
    let cases = [
        ("[matching]\nbeta = 0.0\n", "beta"),
        ("[matching.paper]\nalpha = 1.5\n", "paper.alpha"),
        ("[scene]\ncapacity = 0\n", "capacity"),
        ("[scene]\nmax_abs_coordinate = -1.0\n", "max_abs_coordinate"),
        ("[matching]\nbeta = \"wide\"\n", "beta"),
        ("[matcher]\nmethod = \"magic\"\n", "magic"),
        ("[matcher]\nstale_after_ms = 0\n", "stale_after_ms"),
        (
            "[matcher]\nambiguity_threshold = 2.0\n",
            "ambiguity_threshold",
        ),
        ("[matcher]\nfit_limit = 0.0\n", "fit_limit"),
        ("[matcher]\nfit_limit = nan\n", "fit_limit"),
        ("[matcher]\ntier = \"fast\"\n", "fast"),
        ("[matcher]\nray_max_age_ms = 0\n", "ray_max_age_ms"),
        ("[matcher]\nmax_clock_skew_ms = 500\n", "max_clock_skew_ms"),
        ("[matcher]\nmax_capture_age_ms = 50\n", "max_capture_age_ms"),
        (
            "[matcher]\nmax_queries_per_client_hz = 0.0\n",
            "max_queries_per_client_hz",
        ),
        ("[matcher]\nsolver_nice = 20\n", "solver_nice"),
        ("[ipc]\nprefix = \"\"\n", "prefix"),
        ("[ipc]\nmax_clients = 0\n", "max_clients"),
        ("[feeds]\nsnapshot_rate_hz = 0.0\n", "snapshot_rate_hz"),
        ("[feeds]\ngesture_rate_hz = -1.0\n", "gesture_rate_hz"),
        (
            "[matching.rigid]\ndepth_error = -0.1\n",
            "rigid.depth_error",
        ),
        (
            "[matching.rigid]\nlateral_factor = 0.0\n",
            "rigid.lateral_factor",
        ),
        ("[perception]\nmin_pixels = 0\n", "perception.min_pixels"),
        (
            "[perception]\nmax_image_pixels = 0\n",
            "perception.max_image_pixels",
        ),
        (
            "[perception]\nmax_image_pixels = 4294967297\n",
            "perception.max_image_pixels",
        ),
        ("[perception]\nmax_image_pixels = -1\n", "max_image_pixels"),
        (
            "[segmentation]\nmin_pixels = 0\n",
            "segmentation.min_pixels",
        ),
        (
            "[segmentation]\njump_ratio = -0.1\n",
            "segmentation.jump_ratio",
        ),
        (
            "[segmentation]\ngrow_height_m = 0.02\n",
            "segmentation.grow_height_m",
        ),
        (
            "[segmentation]\nmin_plane_share = 1.5\n",
            "segmentation.min_plane_share",
        ),
        (
            "[perception]\ncentre_offset = -1.0\n",
            "perception.centre_offset",
        ),
        (
            "[perception.robot]\npixel = { a = 0.0, b = 0.0, c = -0.1 }\nsystematic = { a = 0.0, b = 0.005, c = 0.0 }\n",
            "perception.robot.pixel",
        ),
        (
            "[perception.human]\npixel = { a = 0.0, b = 0.0, c = 0.02 }\nsystematic = { a = 0.0, b = nan, c = 0.0 }\n",
            "perception.human.systematic",
        ),
    ];
    for (text, name) in cases {
        let err = Config::parse(text, Path::new("x.toml")).unwrap_err();
        let message = chain(&err);
        assert!(message.contains(name), "{text:?}: {message}");
    }
}

/// The exact tier at the default capacity cannot solve within the
/// freshness budget: refused, naming what would make it fit.
#[test]
fn a_configuration_that_cannot_solve_in_time_is_refused() {
    let text = "[matcher]\nmethod = \"paper\"\ntier = \"exact\"\n";
    let message = chain(&Config::parse(text, Path::new("x.toml")).unwrap_err());
    for part in [
        "[matcher]",
        "paper",
        "exact",
        "256 objects",
        "[scene] capacity",
        "stale_after_ms",
    ] {
        assert!(message.contains(part), "{part}: {message}");
    }
    let smaller = format!("{text}[scene]\ncapacity = 64\n");
    Config::parse(&smaller, Path::new("x.toml")).unwrap();
    let patient = "[matcher]\nmethod = \"paper\"\ntier = \"exact\"\nstale_after_ms = 120000\n";
    Config::parse(patient, Path::new("x.toml")).unwrap();
}

#[test]
fn explicit_path_must_exist_and_wins() {
    let err = Config::load(Some(Path::new("/nonexistent/vref.toml"))).unwrap_err();
    assert!(matches!(err, ConfigError::Read { .. }), "{err:?}");
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("v.toml");
    std::fs::write(&file, "[matching]\nbeta = 3.0\n").unwrap();
    let (config, source) = Config::load(Some(&file)).unwrap();
    assert_eq!(config.matching.beta, 3.0);
    assert_eq!(source, Source::File(file));
}
