//! A second view of a real frame (`vref_perception::reproject`): a camera
//! of coarser resolution sees the same readings where its own pinhole puts
//! them, and a second sensor's noise and colour response are what they
//! are stated to be.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use image::{Luma, Rgb, RgbImage};
use vref_perception::folder::RgbdImages;
use vref_perception::reproject::{Reprojection, SecondSensor, reproject, reproject_scaled};
use vref_perception::{DepthPixels, ImageLimit, Intrinsics};

fn frame(scene: &str) -> RgbdImages {
    RgbdImages::load(
        &vref_testkit::data("osd/learn").join(scene),
        ImageLimit::default(),
    )
    .unwrap()
}

/// Not turned and at half the size, each pixel of the view shows a
/// reading of the frame's pixels it covers, in the frame's colour, and
/// about as many pixels show one as the frame has readings.
#[test]
fn a_half_size_view_shows_the_readings_under_its_pixels() {
    let images = frame("learn20");
    let view = reproject_scaled(
        &images.colour,
        &images.depth,
        images.camera.intrinsics,
        0.0,
        0.5,
    )
    .unwrap();
    let (w, h) = images.colour.dimensions();
    assert_eq!(view.colour.dimensions(), (w / 2, h / 2));
    assert_eq!(view.depth.dimensions(), (w / 2, h / 2));
    assert!((view.intrinsics.fx() - images.camera.intrinsics.fx() / 2.0).abs() < 1e-12);
    let mut shown = 0;
    for (at, source) in view.source.iter().enumerate() {
        let Some(s) = source else { continue };
        shown += 1;
        let (u, v) = (at as u32 % (w / 2), at as u32 / (w / 2));
        let (su, sv) = (s % w, s / w);
        // Its pixel's centre (2u + 0.5, 2v + 0.5) in the frame, within the
        // reading's 2 x 2 footprint at half size.
        assert!(
            (f64::from(su) - (2.0 * f64::from(u) + 0.5)).abs() <= 2.5
                && (f64::from(sv) - (2.0 * f64::from(v) + 0.5)).abs() <= 2.5,
            "({u}, {v}) shows ({su}, {sv})"
        );
        assert_eq!(view.colour.get_pixel(u, v), images.colour.get_pixel(su, sv));
    }
    // As many pixels show a reading as the frame has readings (within a
    // tenth: holes shrink or grow by a pixel at half size).
    let read = images
        .depth
        .pixels()
        .pixels()
        .filter(|d| d.0[0] > 0)
        .count();
    let expected = read as f64 / 4.0;
    assert!(
        (shown as f64 / expected - 1.0).abs() < 0.1,
        "{shown} shown, {expected} expected"
    );
    let full = reproject(&images.colour, &images.depth, images.camera.intrinsics, 0.0).unwrap();
    assert_eq!(full.colour.dimensions(), (w, h));
    for bad in [0.0, -0.5, 1.5, f64::NAN] {
        assert!(
            reproject_scaled(
                &images.colour,
                &images.depth,
                images.camera.intrinsics,
                0.0,
                bad
            )
            .is_err()
        );
    }
}

/// A flat grey view 1.5 m deep with a hole in every tenth pixel.
fn flat_view() -> Reprojection {
    let (w, h) = (200, 150);
    let mut depth = DepthPixels::from_pixel(w, h, Luma([1500]));
    for (i, d) in depth.pixels_mut().enumerate() {
        if i % 10 == 0 {
            d.0[0] = 0;
        }
    }
    Reprojection {
        intrinsics: Intrinsics::new(150.0, 150.0, 99.5, 74.5).unwrap(),
        colour: RgbImage::from_pixel(w, h, Rgb([128, 128, 128])),
        depth,
        source: vec![None; (w * h) as usize],
    }
}

/// The depth noise has the stated sigma (`c z^2`) and no bias, holes stay
/// holes, each channel's gain lies within the stated white balance and
/// exposure, and a seed gives the same view every time.
#[test]
fn a_second_sensor_adds_the_noise_and_colours_it_states() {
    let sensor = SecondSensor {
        depth_c: 0.002,
        white_balance: 0.08,
        exposure: 0.15,
        colour_sigma: 2.0,
        seed: 7,
    };
    let mut view = flat_view();
    sensor.apply(&mut view, 0.001);
    let readings: Vec<f64> = view
        .depth
        .pixels()
        .enumerate()
        .filter(|(i, _)| i % 10 != 0)
        .map(|(_, d)| f64::from(d.0[0]))
        .collect();
    let holes = view
        .depth
        .pixels()
        .enumerate()
        .filter(|(i, d)| i % 10 == 0 && d.0[0] == 0);
    assert_eq!(holes.count(), view.depth.len() / 10);
    let mean = readings.iter().sum::<f64>() / readings.len() as f64;
    let sd =
        (readings.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / readings.len() as f64).sqrt();
    // sigma = 0.002 x 1.5^2 m = 4.5 mm.
    assert!((mean - 1500.0).abs() < 0.1, "mean {mean}");
    assert!((sd / 4.5 - 1.0).abs() < 0.03, "sd {sd}");
    for channel in 0..3 {
        let levels: Vec<f64> = view
            .colour
            .pixels()
            .map(|p| f64::from(p.0[channel]))
            .collect();
        let gain = levels.iter().sum::<f64>() / levels.len() as f64 / 128.0;
        let stated = (1.0 - 0.15) * (1.0 - 0.08) - 0.01..=1.15 * 1.08 + 0.01;
        assert!(stated.contains(&gain), "channel {channel}: gain {gain}");
    }
    let mut again = flat_view();
    sensor.apply(&mut again, 0.001);
    assert_eq!(again.depth, view.depth);
    assert_eq!(again.colour, view.colour);
    let mut other = flat_view();
    SecondSensor { seed: 8, ..sensor }.apply(&mut other, 0.001);
    assert_ne!(other.depth, view.depth);
}
