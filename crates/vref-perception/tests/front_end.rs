#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{Disc, H, W, cosine, draw, intrinsics, two_tone, yellow};
use image::{GrayImage, Luma};
use vref_perception::{
    COLOUR_DIM, CameraNoise, DepthImage, DepthLaw, Detection, FEATURE_DIM, Frame, FrameError,
    FrontEnd, FrontEndSettings, Intrinsics, Mask, PerceptionSettings,
};

fn settings(centre_offset: f64) -> FrontEndSettings {
    FrontEndSettings {
        centre_offset,
        ..PerceptionSettings::default().robot()
    }
}

fn run(
    colour: &image::RgbImage,
    depth: &DepthImage,
    masks: &[GrayImage],
    settings: FrontEndSettings,
) -> (Vec<Detection>, vref_perception::Skipped) {
    let masks: Vec<Mask<'_>> = masks
        .iter()
        .enumerate()
        .map(|(k, m)| Mask {
            id: 10 + k as u64,
            pixels: m,
        })
        .collect();
    let frame = Frame {
        colour,
        depth,
        intrinsics: intrinsics(),
        masks: &masks,
    };
    let mut out = Vec::new();
    let skipped = FrontEnd::new(settings).process(&frame, &mut out).unwrap();
    (out, skipped)
}

#[test]
fn back_projection_matches_hand_computed_points() {
    let k = Intrinsics::new(500.0, 400.0, 320.0, 240.0).unwrap();
    // (420 - 320) * 2 / 500 = 0.4; (140 - 240) * 2 / 400 = -0.5.
    assert_eq!(k.back_project(420.0, 140.0, 2.0), [0.4, -0.5, 2.0]);
    assert_eq!(k.back_project(320.0, 240.0, 0.7), [0.0, 0.0, 0.7]);
    let [u, v] = k.project([0.4, -0.5, 2.0]).unwrap();
    assert!((u - 420.0).abs() < 1e-12 && (v - 140.0).abs() < 1e-12);
    assert!(k.project([0.0, 0.0, -1.0]).is_none());
    let bop = Intrinsics::from_matrix(&[500.0, 0.0, 320.0, 0.0, 400.0, 240.0, 0.0, 0.0, 1.0]);
    assert_eq!(bop.unwrap(), k);
}

#[test]
fn intrinsics_must_be_finite_and_positive() {
    for (fx, fy, cx, cy, name) in [
        (0.0, 500.0, 320.0, 240.0, "fx"),
        (500.0, f64::NAN, 320.0, 240.0, "fy"),
        (500.0, 500.0, f64::INFINITY, 240.0, "cx"),
        (500.0, 500.0, 320.0, -1.0, "cy"),
    ] {
        match Intrinsics::new(fx, fy, cx, cy) {
            Err(FrameError::BadIntrinsics { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{name}: {other:?}"),
        }
    }
    let skewed = [500.0, 1.0, 320.0, 0.0, 500.0, 240.0, 0.0, 0.0, 1.0];
    assert!(matches!(
        Intrinsics::from_matrix(&skewed),
        Err(FrameError::NotPinhole { .. })
    ));
}

/// A flat disc at 1 m: its position is the back-projection of its centre
/// pixel at its depth, pushed back by the centre offset times its radius.
#[test]
fn a_flat_object_is_placed_at_its_centre_pixel_and_depth() {
    let disc = Disc {
        centre: (400.0, 200.0),
        radius: 30.0,
        depth: 1.0,
        look: yellow,
    };
    let (colour, depth, masks) = draw(&[disc], 1.5);
    let (found, _) = run(&colour, &depth, &masks, settings(0.0));
    let p = found[0].position;
    // (400 - 320) / 500 = 0.16, (200 - 240) / 500 = -0.08.
    for (got, want) in p.iter().zip([0.16, -0.08, 1.0]) {
        assert!((got - want).abs() < 1e-3, "{p:?}");
    }
    let (found, _) = run(&colour, &depth, &masks, settings(0.5));
    let area = masks[0].pixels().filter(|p| p.0[0] != 0).count() as f64;
    let z = 1.0 + 0.5 * (area / std::f64::consts::PI).sqrt() / 500.0;
    let want = intrinsics().back_project(400.0, 200.0, z);
    for (got, want) in found[0].position.iter().zip(want) {
        assert!(
            (got - want).abs() < 1e-3,
            "{:?} vs {want:?}",
            found[0].position
        );
    }
}

/// Holes, background seen at the outline and flying pixels do not move
/// the object.
#[test]
fn holes_edges_and_flying_pixels_are_ignored() {
    let disc = Disc {
        centre: (300.0, 260.0),
        radius: 25.0,
        depth: 0.8,
        look: yellow,
    };
    let (colour, depth, masks) = draw(&[disc], 1.6);
    let mut broken = depth.pixels().clone();
    let mut k = 0;
    for (u, v, p) in masks[0].enumerate_pixels() {
        if p.0[0] == 0 {
            continue;
        }
        k += 1;
        let dx = f64::from(u) - 300.0;
        let dy = f64::from(v) - 260.0;
        let edge = (dx * dx + dy * dy).sqrt() > 23.0;
        let value = if edge {
            // The outline reads the background behind the object.
            1600
        } else if k % 7 == 0 {
            0 // a hole
        } else if k % 11 == 0 {
            1200 // flying pixel halfway to the background
        } else {
            continue;
        };
        broken.put_pixel(u, v, Luma([value]));
    }
    let broken = DepthImage::new(broken, 0.001).unwrap();
    let (found, _) = run(&colour, &broken, &masks, settings(0.0));
    let want = intrinsics().back_project(300.0, 260.0, 0.8);
    for (got, want) in found[0].position.iter().zip(want) {
        assert!(
            (got - want).abs() < 2e-3,
            "{:?} vs {want:?}",
            found[0].position
        );
    }
}

#[test]
fn small_masks_and_masks_without_depth_are_skipped_and_counted() {
    let discs = [
        Disc {
            centre: (100.0, 100.0),
            radius: 5.0, // about 80 pixels, under the minimum of 150
            depth: 1.0,
            look: yellow,
        },
        Disc {
            centre: (300.0, 300.0),
            radius: 20.0,
            depth: 1.0,
            look: yellow,
        },
        Disc {
            centre: (500.0, 200.0),
            radius: 20.0,
            depth: 1.0,
            look: yellow,
        },
    ];
    let (colour, depth, mut masks) = draw(&discs, 2.0);
    let mut holes = depth.pixels().clone();
    for (u, v, p) in masks[2].enumerate_pixels() {
        if p.0[0] != 0 {
            holes.put_pixel(u, v, Luma([0]));
        }
    }
    let holes = DepthImage::new(holes, 0.001).unwrap();
    masks.push(GrayImage::new(W, H)); // empty
    let (found, skipped) = run(&colour, &holes, &masks, settings(0.0));
    assert_eq!(found.iter().map(|d| d.id).collect::<Vec<_>>(), [11]);
    assert_eq!((skipped.too_small, skipped.no_depth), (2, 1));
}

#[test]
fn images_of_another_size_are_refused_naming_them() {
    let (colour, depth, masks) = draw(
        &[Disc {
            centre: (100.0, 100.0),
            radius: 20.0,
            depth: 1.0,
            look: yellow,
        }],
        2.0,
    );
    let small = GrayImage::new(W / 2, H);
    let masks = [
        Mask {
            id: 1,
            pixels: &masks[0],
        },
        Mask {
            id: 2,
            pixels: &small,
        },
    ];
    let mut front_end = FrontEnd::new(settings(0.0));
    let frame = Frame {
        colour: &colour,
        depth: &depth,
        intrinsics: intrinsics(),
        masks: &masks,
    };
    let err = front_end.process(&frame, &mut Vec::new()).unwrap_err();
    assert!(matches!(err, FrameError::MaskSize { id: 2, .. }), "{err}");
    let short = DepthImage::new(image::ImageBuffer::new(W, H - 1), 0.001).unwrap();
    let frame = Frame {
        depth: &short,
        masks: &masks[..1],
        ..frame
    };
    let err = front_end.process(&frame, &mut Vec::new()).unwrap_err();
    assert!(matches!(err, FrameError::DepthSize { .. }), "{err}");
    assert!(DepthImage::new(image::ImageBuffer::new(1, 1), 0.0).is_err());
}

/// The median of n readings errs by sqrt(pi / 2n) of one reading's noise;
/// the systematic part stays; the three axes together are the error along
/// the ray.
#[test]
fn the_error_model_combines_pixel_noise_and_systematic_error() {
    let noise = CameraNoise {
        pixel: DepthLaw {
            a: 0.0,
            b: 0.0,
            c: 0.01,
        },
        systematic: DepthLaw {
            a: 0.001,
            b: 0.01,
            c: 0.0,
        },
    };
    let (z, n) = (2.0, 200);
    let pixel = 0.01 * 4.0 * (std::f64::consts::PI / 400.0).sqrt();
    let systematic = 0.001 + 0.02;
    let want = pixel.hypot(systematic);
    assert!((noise.depth_sigma(z, n) - want).abs() < 1e-12);
    let p = [0.6, -0.3, 2.0];
    let sigma = noise.position_sigma(p, n);
    let range = (0.36f64 + 0.09 + 4.0).sqrt();
    let along = sigma.iter().map(|s| s * s).sum::<f64>().sqrt();
    assert!((along - range * want / z).abs() < 1e-12, "{sigma:?}");
    assert!((sigma[2] - want).abs() < 1e-12);
    // More pixels, less noise; never below the systematic part.
    assert!(noise.depth_sigma(z, 10_000) < noise.depth_sigma(z, 100));
    assert!(noise.depth_sigma(z, 1_000_000) >= systematic);
}

#[test]
fn features_do_not_depend_on_the_mask_size() {
    let draw_at = |radius: f64| {
        let disc = Disc {
            centre: (320.0, 240.0),
            radius,
            depth: 1.0,
            look: two_tone,
        };
        let (colour, depth, masks) = draw(&[disc], 2.0);
        run(&colour, &depth, &masks, settings(0.0)).0[0].feature
    };
    let small = draw_at(18.0);
    let large = draw_at(90.0);
    assert_eq!(small.len(), FEATURE_DIM);
    let (cs, ss) = small.split_at(COLOUR_DIM);
    let (cl, sl) = large.split_at(COLOUR_DIM);
    assert!(cosine(cs, cl) > 0.99, "colour {}", cosine(cs, cl));
    assert!(cosine(ss, sl) > 0.95, "shape {}", cosine(ss, sl));
    // Each block is unit length.
    for block in [cs, ss, cl, sl] {
        let norm = block.iter().map(|v| v * v).sum::<f32>().sqrt();
        assert!((norm - 1.0).abs() < 1e-5);
    }
}

#[test]
fn colour_survives_white_balance_but_tells_colours_apart() {
    let disc = |look| Disc {
        centre: (320.0, 240.0),
        radius: 40.0,
        depth: 1.0,
        look,
    };
    let colour_block = |look, gains: [f32; 3]| {
        let (mut colour, depth, masks) = draw(&[disc(look)], 2.0);
        for p in colour.pixels_mut() {
            for (c, gain) in p.0.iter_mut().zip(gains) {
                *c = (f32::from(*c) * gain).min(255.0) as u8;
            }
        }
        run(&colour, &depth, &masks, settings(0.0)).0[0].feature[..COLOUR_DIM].to_vec()
    };
    let plain = colour_block(yellow, [1.0; 3]);
    let balanced = colour_block(yellow, [1.08, 1.0, 0.92]);
    assert!(
        cosine(&plain, &balanced) > 0.95,
        "{}",
        cosine(&plain, &balanced)
    );
    let other = colour_block(two_tone, [1.0; 3]);
    assert!(cosine(&plain, &other) < 0.5, "{}", cosine(&plain, &other));
}

/// A mask covering every pixel (a segmenter's background, an inverted
/// mask) is no object: skipped and counted, the other masks measured.
#[test]
fn a_mask_over_the_whole_frame_is_skipped_and_counted() {
    let (colour, depth, mut masks) = draw(
        &[Disc {
            centre: (160.0, 120.0),
            radius: 30.0,
            depth: 0.8,
            look: yellow,
        }],
        1.5,
    );
    masks.push(GrayImage::from_pixel(W, H, Luma([255])));
    let (found, skipped) = run(&colour, &depth, &masks, settings(0.0));
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].id, 10);
    assert_eq!(skipped.whole_frame, 1);
}
