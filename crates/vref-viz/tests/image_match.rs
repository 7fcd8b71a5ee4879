#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! The picture over real images: outlines coloured by what the method
//! made of each object, drawn where the masks are.

mod common;

use common::Picture;
use vref_scene::{Limits, SceneGraph, SceneObject, ScenePair};
use vref_viz::{ImageMatchPicture, ImageObject, ViewImage};

const W: u32 = 320;
const H: u32 = 240;
const GAP: u32 = 16;
const TOP: u32 = 44;

fn graph(ids: &[u64]) -> SceneGraph {
    let objects = ids
        .iter()
        .map(|&id| SceneObject::new(id, [id as f64 * 0.1, 0.0, 1.0], Vec::new()))
        .collect();
    SceneGraph::new(objects, None, &Limits::default()).unwrap()
}

/// A square outline of side 20 at (u, v).
fn square(u: u32, v: u32) -> Vec<(u32, u32)> {
    (0..20)
        .flat_map(|k| [(u + k, v), (u + k, v + 19), (u, v + k), (u + 19, v + k)])
        .collect()
}

fn pixel(p: &Picture, x: u32, y: u32) -> [u8; 3] {
    let i = ((y * p.width + x) * 3) as usize;
    [p.rgb[i], p.rgb[i + 1], p.rgb[i + 2]]
}

#[test]
fn outlines_are_green_for_right_pairs_and_red_for_wrong_ones() {
    let rgb = vec![90u8; (W * H * 3) as usize];
    let objects = |first: u64| {
        vec![
            ImageObject {
                id: first,
                centre: [60.0, 60.0],
                outline: square(50, 50),
            },
            ImageObject {
                id: first + 1,
                centre: [160.0, 160.0],
                outline: square(150, 150),
            },
        ]
    };
    let human = ViewImage {
        rgb: &rgb,
        width: W,
        height: H,
        objects: objects(1),
    };
    let robot = ViewImage {
        rgb: &rgb,
        width: W,
        height: H,
        objects: objects(11),
    };
    let pair = ScenePair::new(
        "s".into(),
        graph(&[11, 12]),
        graph(&[1, 2]),
        vec![(1, 11), (2, 12)],
    )
    .unwrap();
    let is = |c: [u8; 3], green: bool| {
        if green {
            c[1] > 150 && c[0] < 60
        } else {
            c[0] > 200 && c[1] < 60
        }
    };
    for (predicted, right) in [
        (vec![(1, 11), (2, 12)], true),
        (vec![(1, 12), (2, 11)], false),
    ] {
        let png = ImageMatchPicture::new(&pair, &predicted, "m", &human, &robot)
            .render_png()
            .unwrap();
        let p = Picture::decode(&png);
        assert_eq!((p.width, p.height), (2 * W + GAP, H + TOP + 30));
        // A corner of each outline, in both halves; the image elsewhere.
        for left in [0, W + GAP] {
            for (u, v) in [(50, 50), (150, 150)] {
                let c = pixel(&p, left + u, TOP + v);
                assert!(is(c, right), "{c:?} at ({u}, {v}), right {right}");
            }
            assert_eq!(pixel(&p, left + 300, TOP + 20), [90, 90, 90]);
        }
    }
    // An unknown predicted id is an error, not a picture.
    let bad = [(1, 99)];
    assert!(
        ImageMatchPicture::new(&pair, &bad, "m", &human, &robot)
            .render_png()
            .is_err()
    );
}
