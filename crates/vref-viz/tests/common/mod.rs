//! Scenes and PNG decoding shared by the tests.
#![allow(dead_code)]

use std::io::Cursor;

use vref_scene::{Limits, SceneGraph, SceneObject, ScenePair};

/// A decoded RGB picture.
pub struct Picture {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Picture {
    pub fn decode(png_bytes: &[u8]) -> Picture {
        let mut decoder = png::Decoder::new(Cursor::new(png_bytes));
        // Palette pictures come out as RGB.
        decoder.set_transformations(png::Transformations::EXPAND);
        let mut reader = decoder.read_info().expect("PNG header");
        let mut rgb = vec![0; reader.output_buffer_size().expect("buffer size")];
        let info = reader.next_frame(&mut rgb).expect("PNG data");
        assert_eq!(info.color_type, png::ColorType::Rgb);
        rgb.truncate(info.buffer_size());
        Picture {
            width: info.width,
            height: info.height,
            rgb,
        }
    }

    /// Pixels for which `pred` holds.
    pub fn count(&self, pred: impl Fn([u8; 3]) -> bool) -> usize {
        self.rgb
            .chunks_exact(3)
            .filter(|p| pred([p[0], p[1], p[2]]))
            .count()
    }
}

/// Saturated green, as the right-match lines are drawn (not grey, not text).
pub fn greenish([r, g, b]: [u8; 3]) -> bool {
    g > 120 && i32::from(g) - i32::from(r) > 80 && i32::from(g) - i32::from(b) > 40
}

/// Saturated red, as the wrong-match lines are drawn.
pub fn reddish([r, g, b]: [u8; 3]) -> bool {
    r > 150 && i32::from(r) - i32::from(g) > 100 && i32::from(r) - i32::from(b) > 100
}

pub fn not_white([r, g, b]: [u8; 3]) -> bool {
    r < 250 || g < 250 || b < 250
}

fn graph(objects: Vec<SceneObject>) -> SceneGraph {
    SceneGraph::new(objects, None, &Limits::default()).expect("valid graph")
}

/// Like a CMU House pair: `n` landmarks in pixels (z = 0), the robot view
/// shifted, with other ids (human id i is robot id 100 + i), fully paired.
pub fn cmu_like(n: usize) -> ScenePair {
    let human: Vec<SceneObject> = (0..n)
        .map(|i| {
            let t = i as f64;
            let position = [100.0 + 37.0 * (t * 1.3).sin() * t, 80.0 + 9.0 * t, 0.0];
            SceneObject::new(i as u64, position, Vec::new())
        })
        .collect();
    let robot = human
        .iter()
        .map(|o| {
            let p = o.position;
            SceneObject::new(100 + o.id, [p.x + 25.0, p.y - 10.0, 0.0], Vec::new())
        })
        .collect();
    let truth = (0..n as u64).map(|i| (i, 100 + i)).collect();
    ScenePair::new("cmu-like".to_owned(), graph(robot), graph(human), truth).expect("valid pair")
}

/// The true pairs of `pair`, with the first `wrong` of them crossed over so
/// that they are wrong.
pub fn prediction(pair: &ScenePair, wrong: usize) -> Vec<(u64, u64)> {
    let mut pairs = pair.ground_truth.clone();
    for k in (0..wrong).step_by(2) {
        if k + 1 < pairs.len() {
            let (a, b) = (pairs[k].1, pairs[k + 1].1);
            pairs[k].1 = b;
            pairs[k + 1].1 = a;
        }
    }
    pairs
}

/// A pair given by positions; human id i pairs robot id i where `truth`
/// says so.
pub fn pair_of(human: &[[f64; 3]], robot: &[[f64; 3]], truth: &[(u64, u64)]) -> ScenePair {
    let objects = |ps: &[[f64; 3]]| {
        ps.iter()
            .enumerate()
            .map(|(i, &p)| SceneObject::new(i as u64, p, Vec::new()))
            .collect()
    };
    ScenePair::new(
        "hand-made".to_owned(),
        graph(objects(robot)),
        graph(objects(human)),
        truth.to_vec(),
    )
    .expect("valid pair")
}
