#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{Picture, cmu_like, greenish, not_white, pair_of, prediction, reddish};
use vref_scene::Side;
use vref_viz::{MatchPicture, Projection, RenderError, Size};

#[test]
fn renders_a_png_of_the_requested_size() {
    let pair = cmu_like(30);
    let predicted = prediction(&pair, 4);
    for size in [Size::new(1200, 600), Size::new(777, 333)] {
        let png = MatchPicture::new(&pair, &predicted, "paper")
            .render_png(size)
            .unwrap();
        let picture = Picture::decode(&png);
        assert_eq!((picture.width, picture.height), (size.width, size.height));
        assert!(picture.count(not_white) > 1000, "picture is blank");
    }
}

#[test]
fn right_matches_are_green_and_wrong_ones_red() {
    let pair = cmu_like(30);
    let size = Size::new(1200, 600);
    let all_right = prediction(&pair, 0);
    let png = MatchPicture::new(&pair, &all_right, "sm")
        .render_png(size)
        .unwrap();
    let picture = Picture::decode(&png);
    // The legend holds a short red line; the scene none.
    let legend_red = picture.count(reddish);
    assert!(picture.count(greenish) > 3000);

    let some_wrong = prediction(&pair, 6);
    let png = MatchPicture::new(&pair, &some_wrong, "sm")
        .render_png(size)
        .unwrap();
    let picture = Picture::decode(&png);
    assert!(
        picture.count(reddish) > legend_red + 1000,
        "six wrong matches drew no red lines"
    );
}

#[test]
fn draws_a_view_of_one_object() {
    let pair = pair_of(
        &[[3.0, 4.0, 0.0]],
        &[[1.0, 1.0, 0.0], [5.0, 2.0, 0.0], [2.0, 7.0, 0.0]],
        &[(0, 2)],
    );
    let png = MatchPicture::new(&pair, &[(0, 2)], "rrwm")
        .render_png(Size::new(640, 320))
        .unwrap();
    let picture = Picture::decode(&png);
    assert_eq!((picture.width, picture.height), (640, 320));
    assert!(picture.count(greenish) > 100);
}

#[test]
fn draws_unmatched_objects_and_views_in_3d() {
    // Camera frames in metres, every object in front of its camera; human
    // object 2 has no partner and no prediction.
    let pair = pair_of(
        &[[0.1, 0.2, 1.0], [-0.3, 0.1, 1.4], [0.0, -0.1, 0.8]],
        &[[0.2, 0.1, 1.1], [-0.1, 0.3, 1.2]],
        &[(0, 1), (1, 0)],
    );
    for projection in [
        Projection::Auto,
        Projection::TopDown,
        Projection::Perspective,
    ] {
        let png = MatchPicture::new(&pair, &[(0, 1), (1, 0)], "paper")
            .projection(projection)
            .render_png(Size::new(900, 450))
            .unwrap();
        assert!(Picture::decode(&png).count(greenish) > 100);
    }
}

#[test]
fn refuses_a_prediction_naming_an_unknown_object() {
    let pair = cmu_like(5);
    let error = MatchPicture::new(&pair, &[(0, 999)], "sm")
        .render_png(Size::new(800, 400))
        .unwrap_err();
    assert!(
        matches!(
            error,
            RenderError::UnknownPredictedId {
                side: Side::Robot,
                id: 999
            }
        ),
        "{error}"
    );
}

#[test]
fn refuses_sizes_out_of_range() {
    let pair = cmu_like(5);
    let picture = MatchPicture::new(&pair, &[], "sm");
    for size in [
        Size::new(0, 600),
        Size::new(1200, 10),
        Size::new(50_000, 600),
    ] {
        let error = picture.render_png(size).unwrap_err();
        assert!(matches!(error, RenderError::BadSize { .. }), "{error}");
    }
}

#[test]
fn saves_the_picture_to_a_file() {
    let pair = cmu_like(8);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("match.png");
    MatchPicture::new(&pair, &prediction(&pair, 2), "paper")
        .save(&out, Size::new(600, 300))
        .unwrap();
    let picture = Picture::decode(&std::fs::read(&out).unwrap());
    assert_eq!((picture.width, picture.height), (600, 300));

    let missing = dir.path().join("no/such/dir/match.png");
    let error = MatchPicture::new(&pair, &[], "paper")
        .save(&missing, Size::new(600, 300))
        .unwrap_err();
    assert!(matches!(error, RenderError::Write { .. }), "{error}");
}
