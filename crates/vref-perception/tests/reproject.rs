//! A second view of a real frame (`vref_perception::reproject`): a camera
//! of coarser resolution sees the same readings where its own pinhole puts
//! them, and a second sensor's noise and colour response are what they
//! are stated to be.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use image::{Luma, Rgb, RgbImage};
use vref_perception::folder::RgbdImages;
use vref_perception::reproject::{Reprojection, SecondSensor, Walk, reproject, reproject_walked};
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
    let half = |scale| Walk {
        yaw_deg: 0.0,
        scale,
        moved: None,
    };
    let view = reproject_walked(
        &images.colour,
        &images.depth,
        images.camera.intrinsics,
        &half(0.5),
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
            reproject_walked(
                &images.colour,
                &images.depth,
                images.camera.intrinsics,
                &half(bad)
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

/// An object moved 0.2 m along the table shows in the view 0.2 m from
/// where it was read, parallel to the table (its height kept); one that
/// would land next to another object is refused. learn33 is a cluttered
/// table, so both happen.
#[test]
fn a_moved_object_lands_where_it_was_moved_or_is_refused() {
    use vref_perception::reproject::{Moved, ReprojectError};
    let images = frame("learn33");
    let objects = image::open(vref_testkit::data("osd/learn/learn33/label.png"))
        .unwrap()
        .into_luma16();
    let k = images.camera.intrinsics;
    let metres = images.depth.metres_per_unit();
    let (w, _) = images.colour.dimensions();
    let point =
        |d: u16, u: u32, v: u32| k.back_project(f64::from(u), f64::from(v), f64::from(d) * metres);
    let (mut moved, mut refused) = (0, 0);
    let present: std::collections::BTreeSet<u16> = objects
        .as_raw()
        .iter()
        .map(|&l| vref_testkit::osd_object(l))
        .filter(|&o| o > 0)
        .collect();
    for object in present {
        let readings: Vec<bool> = objects
            .as_raw()
            .iter()
            .map(|&l| vref_testkit::osd_object(l) == object)
            .collect();
        let walk = Walk {
            yaw_deg: 0.0,
            scale: 1.0,
            moved: Some(Moved {
                readings: &readings,
                metres: 0.2,
            }),
        };
        let view = match reproject_walked(&images.colour, &images.depth, k, &walk) {
            Ok(view) => view,
            Err(ReprojectError::NotFree(_)) => {
                refused += 1;
                continue;
            }
            Err(e) => panic!("object {object}: {e}"),
        };
        moved += 1;
        let mut shifts = Vec::new();
        for (at, source) in view.source.iter().enumerate() {
            let Some(s) = source.map(|s| s as usize) else {
                continue;
            };
            if !readings[s] {
                continue;
            }
            let (u, v) = ((at as u32) % w, (at as u32) / w);
            let (su, sv) = ((s as u32) % w, (s as u32) / w);
            let seen = point(view.depth.get_pixel(u, v).0[0], u, v);
            let read = point(images.depth.pixels().get_pixel(su, sv).0[0], su, sv);
            shifts.push(std::array::from_fn::<f64, 3, _>(|i| seen[i] - read[i]));
        }
        assert!(
            shifts.len() > 100,
            "object {object}: {} readings seen",
            shifts.len()
        );
        let mean: [f64; 3] =
            std::array::from_fn(|i| shifts.iter().map(|s| s[i]).sum::<f64>() / shifts.len() as f64);
        let length = mean.iter().map(|x| x * x).sum::<f64>().sqrt();
        // Within the pixel footprint's error at about a metre.
        assert!(
            (length - 0.2).abs() < 0.01,
            "object {object} moved {length} m"
        );
    }
    assert!(moved > 0 && refused > 0, "{moved} moved, {refused} refused");
}
