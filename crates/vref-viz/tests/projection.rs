#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::pair_of;
use vref_viz::Projection;

fn resolve(human: &[[f64; 3]], robot: &[[f64; 3]]) -> Projection {
    let pair = pair_of(human, robot, &[]);
    Projection::Auto.resolve(&[&pair.human, &pair.robot])
}

#[test]
fn image_data_is_drawn_in_pixels() {
    let flat = [[10.0, 20.0, 0.0], [30.0, 5.0, 0.0]];
    assert_eq!(resolve(&flat, &flat), Projection::Pixels);
    // Each view flat at its own depth is still an image.
    let other = [[1.0, 2.0, 7.0], [3.0, 4.0, 7.0]];
    assert_eq!(resolve(&flat, &other), Projection::Pixels);
}

#[test]
fn objects_in_front_of_the_cameras_are_drawn_as_seen() {
    let human = [[0.1, 0.2, 1.0], [-0.2, 0.0, 1.5]];
    let robot = [[0.0, 0.1, 0.9], [0.3, 0.2, 1.2]];
    assert_eq!(resolve(&human, &robot), Projection::Perspective);
}

#[test]
fn objects_behind_a_camera_are_drawn_from_above() {
    let human = [[0.1, 0.2, 1.0], [-0.2, 0.0, 1.5]];
    let robot = [[0.0, 0.1, -0.5], [0.3, 0.2, 1.2]];
    assert_eq!(resolve(&human, &robot), Projection::TopDown);
}

#[test]
fn an_explicit_projection_is_kept() {
    let flat = [[10.0, 20.0, 0.0], [30.0, 5.0, 0.0]];
    let pair = pair_of(&flat, &flat, &[]);
    let views = [&pair.human, &pair.robot];
    assert_eq!(Projection::TopDown.resolve(&views), Projection::TopDown);
}

#[test]
fn names_parse_back() {
    for name in Projection::NAMES {
        let projection: Projection = name.parse().unwrap();
        assert_eq!(projection.name(), name);
        assert_eq!(projection.to_string(), name);
    }
    let error = "sideways".parse::<Projection>().unwrap_err();
    assert!(error.to_string().contains("sideways"), "{error}");
}
