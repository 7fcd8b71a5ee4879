//! A camera whose lens bends rays: its frame folder states the distortion
//! in camera.json, and the objects come out where they are, where a
//! pinhole reading of the same images puts those near the edges
//! centimetres off.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use image::{Luma, Rgb, RgbImage};
use vref_perception::folder::{FolderError, RgbdImages};
use vref_perception::{
    DepthPixels, Distortion, Frame, FrontEnd, ImageLimit, LabelImage, Mask, PerceptionSettings,
    label_masks,
};

const W: u32 = 640;
const H: u32 = 480;
const FX: f64 = 525.0;
const CX: f64 = 319.5;
const CY: f64 = 239.5;
/// A wide lens's barrel: about 5 % at the image's corners.
const D: [f64; 5] = [-0.12, 0.05, 0.0008, -0.0005, 0.0];

/// Balls on a floor 1.2 m ahead: centres in the camera frame, radius,
/// colour. Spread to the image's edges, where the lens bends most.
const BALLS: [([f64; 3], f64, [u8; 3]); 5] = [
    ([0.0, 0.0, 1.1], 0.05, [200, 40, 30]),
    ([-0.55, -0.35, 1.1], 0.05, [40, 60, 210]),
    ([0.55, 0.38, 1.1], 0.05, [220, 200, 40]),
    ([0.58, -0.36, 1.1], 0.05, [30, 170, 60]),
    ([-0.56, 0.37, 1.1], 0.05, [160, 40, 170]),
];
const FLOOR_Z: f64 = 1.2;

/// Depth (mm), colour and labels of the scene as a camera with `lens`
/// records it (each raw pixel's own ray, cast).
fn render(lens: &Distortion) -> (RgbImage, DepthPixels, LabelImage) {
    let mut colour = RgbImage::from_pixel(W, H, Rgb([120, 110, 100]));
    let mut depth = DepthPixels::new(W, H);
    let mut labels = LabelImage::new(W, H);
    for v in 0..H {
        for u in 0..W {
            let (x, y) = lens.undistort((f64::from(u) - CX) / FX, (f64::from(v) - CY) / FX);
            // Along the ray (x, y, 1): the floor at z = FLOOR_Z, or the
            // nearest ball in front of it.
            let ray = [x, y, 1.0];
            let mut hit = (FLOOR_Z, 0u16, [120, 110, 100]);
            for (k, &(c, r, look)) in BALLS.iter().enumerate() {
                let rr = ray.iter().map(|a| a * a).sum::<f64>();
                let rc = ray.iter().zip(c).map(|(a, b)| a * b).sum::<f64>();
                let cc = c.iter().map(|a| a * a).sum::<f64>();
                let disc = rc * rc - rr * (cc - r * r);
                if disc >= 0.0 {
                    let t = (rc - disc.sqrt()) / rr;
                    if t < hit.0 {
                        hit = (t, k as u16 + 1, look);
                    }
                }
            }
            depth.put_pixel(u, v, Luma([(hit.0 * 1000.0).round() as u16]));
            labels.put_pixel(u, v, Luma([hit.1]));
            colour.put_pixel(u, v, Rgb(hit.2));
        }
    }
    (colour, depth, labels)
}

fn write_frame(dir: &Path, camera: &str, lens: &Distortion) {
    let (colour, depth, labels) = render(lens);
    colour.save(dir.join("rgb.png")).unwrap();
    depth.save(dir.join("depth.png")).unwrap();
    labels.save(dir.join("masks.png")).unwrap();
    std::fs::write(dir.join("camera.json"), camera).unwrap();
}

/// Each ball's position error (metres), by label, of the frame in `dir`.
fn errors(dir: &Path) -> Vec<f64> {
    let frame = RgbdImages::load(dir, ImageLimit::default()).unwrap();
    let masks = label_masks(frame.masks.as_ref().unwrap());
    let masks: Vec<Mask<'_>> = masks
        .iter()
        .map(|m| Mask {
            id: u64::from(m.label),
            pixels: &m.pixels,
        })
        .collect();
    let mut front_end = FrontEnd::new(PerceptionSettings::default().robot());
    let mut objects = Vec::new();
    front_end
        .process(
            &Frame {
                colour: &frame.colour,
                depth: &frame.depth,
                intrinsics: frame.camera.intrinsics,
                masks: &masks,
            },
            &mut objects,
        )
        .unwrap();
    assert_eq!(objects.len(), BALLS.len(), "every ball is an object");
    objects
        .iter()
        .map(|o| {
            let truth = BALLS[o.id as usize - 1].0;
            let e: f64 = o
                .position
                .iter()
                .zip(truth)
                .map(|(a, b)| (a - b).powi(2))
                .sum();
            e.sqrt()
        })
        .collect()
}

fn barrel() -> Distortion {
    Distortion::new("plumb_bob", &D).unwrap().unwrap()
}

fn camera(lens: &str) -> String {
    format!(
        r#"{{"fx": {FX}, "fy": {FX}, "cx": {CX}, "cy": {CY}, "width": {W}, "height": {H}{lens}}}"#
    )
}

#[test]
fn a_frame_of_a_bending_lens_is_rectified_and_its_objects_placed_right() {
    // A wide lens's barrel, and a fisheye (equidistant: the ray's angle,
    // not its tangent, is what the image spaces evenly).
    for (model, d) in [("plumb_bob", D.to_vec()), ("equidistant", vec![0.0; 4])] {
        let lens = Distortion::new(model, &d).unwrap().unwrap();
        let d = d.iter().map(f64::to_string).collect::<Vec<_>>().join(", ");
        let rectified = tempfile::tempdir().unwrap();
        write_frame(
            rectified.path(),
            &camera(&format!(r#", "distortion_model": "{model}", "d": [{d}]"#)),
            &lens,
        );
        let pinhole = tempfile::tempdir().unwrap();
        write_frame(pinhole.path(), &camera(""), &lens);
        let with_lens = errors(rectified.path());
        let without = errors(pinhole.path());
        eprintln!("{model}: errors with the lens {with_lens:.4?}, read as a pinhole {without:.4?}");
        // The centre ball is where it is either way; the corner ones only
        // with the lens.
        assert!(
            with_lens.iter().all(|&e| e < 0.01),
            "{model}: {with_lens:?}"
        );
        assert!(without[0] < 0.01, "{model}: {without:?}");
        assert!(
            without[1..].iter().all(|&e| e > 0.015),
            "{model}: {without:?}"
        );
    }
}

#[test]
fn a_lens_that_cannot_be_used_is_refused_naming_the_camera_file() {
    for (lens, why) in [
        (
            r#", "distortion_model": "fov", "d": [0.1]"#,
            "distortion model \"fov\" is not supported",
        ),
        (
            r#", "distortion_model": "plumb_bob", "d": [0.1, 0, 0]"#,
            "takes 4 or 5 coefficients, 3 given",
        ),
        (
            r#", "d": [0.1, 0, 0, 0, 0]"#,
            "coefficients given without a model",
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        write_frame(dir.path(), &camera(lens), &barrel());
        let err = RgbdImages::load(dir.path(), ImageLimit::default()).unwrap_err();
        assert!(matches!(err, FolderError::Lens { .. }), "{err:?}");
        let message = format!("{err}: {}", std::error::Error::source(&err).unwrap());
        assert!(
            message.contains("camera.json") && message.contains(why),
            "{message}"
        );
    }
    // All zero is no distortion, but for a fisheye.
    let dir = tempfile::tempdir().unwrap();
    write_frame(
        dir.path(),
        &camera(r#", "distortion_model": "fov", "d": [0]"#),
        &barrel(),
    );
    let frame = RgbdImages::load(dir.path(), ImageLimit::default()).unwrap();
    assert_eq!(frame.camera.lens, None);
}

/// The depth noise measured on a rectified frame is the raw frame's: the
/// nearest-pixel lookup repeats or skips a reading here and there, which
/// must not move what the segmenter's thresholds are set from. Real
/// Kinect frames (OSD learn), barrel and pincushion lenses; the ratios
/// print with `--nocapture`.
#[test]
fn rectifying_keeps_the_measured_depth_noise() {
    let intrinsics = vref_perception::Intrinsics::new(FX, FX, CX, CY).unwrap();
    for scene in ["learn3", "learn20", "learn36", "learn40"] {
        let path = vref_testkit::data("osd/learn")
            .join(scene)
            .join("depth.png");
        let raw = vref_perception::load_depth(&path, ImageLimit::default()).unwrap();
        let raw = vref_perception::DepthImage::new(raw, 0.001).unwrap();
        let before = vref_perception::pixel_noise(&raw).unwrap().c;
        for d in [[-0.05, 0.01, 0.0, 0.0, 0.0], D, [0.1, 0.0, 0.0, 0.0, 0.0]] {
            let lens = Distortion::new("plumb_bob", &d).unwrap().unwrap();
            let rectified = vref_perception::Rectifier::new(&intrinsics, &lens, W, H)
                .apply(raw.pixels(), Luma([0]))
                .unwrap();
            let rectified = vref_perception::DepthImage::new(rectified, 0.001).unwrap();
            let after = vref_perception::pixel_noise(&rectified).unwrap().c;
            eprintln!("{scene} d {d:?}: c {before:.5} raw, {after:.5} rectified");
            assert!(
                (after / before - 1.0).abs() < 0.05,
                "{scene} {d:?}: {before} -> {after}"
            );
        }
    }
}

/// A camera written by `Camera::to_json` reads back as the same camera:
/// pinhole or with a lens of each model, with its size or without.
#[test]
fn a_camera_written_as_json_reads_back_the_same() {
    let intrinsics = vref_perception::Intrinsics::new(FX, FX + 2.0, CX, CY).unwrap();
    let lenses = [
        None,
        Some(barrel()),
        Distortion::new(
            "rational_polynomial",
            &[0.1, -0.02, 0.001, 0.0, 0.0, 0.05, 0.0, 0.0],
        )
        .unwrap(),
        Distortion::new("equidistant", &[0.01, 0.0, 0.0, 0.0]).unwrap(),
    ];
    let dir = tempfile::tempdir().unwrap();
    for lens in lenses {
        for size in [None, Some((W, H))] {
            let camera = vref_perception::folder::Camera {
                intrinsics,
                metres_per_unit: 0.0001,
                size,
                lens,
            };
            let path = dir.path().join("camera.json");
            std::fs::write(&path, camera.to_json()).unwrap();
            let (read, unread) = vref_perception::folder::Camera::read(&path).unwrap();
            assert_eq!(read, camera, "{}", camera.to_json());
            assert!(unread.is_empty(), "{unread:?}");
        }
    }
}
