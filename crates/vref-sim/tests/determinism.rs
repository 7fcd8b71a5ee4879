#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! A dataset is a pure function of preset, seed and count.

use vref_scene::DatasetWriter;
use vref_sim::{Generator, Preset};

fn dataset(preset: Preset, seed: u64, count: u64) -> Vec<u8> {
    let generator = Generator::new(preset.config(), seed)
        .unwrap()
        .named(preset.name());
    let mut writer = DatasetWriter::new(Vec::new());
    for scene in generator.scenes(count) {
        writer.write(&scene.unwrap().pair).unwrap();
    }
    writer.finish().unwrap()
}

#[test]
fn same_seed_gives_byte_identical_files() {
    for preset in Preset::ALL {
        let first = dataset(preset, 42, 8);
        let second = dataset(preset, 42, 8);
        assert_eq!(first.iter().filter(|&&b| b == b'\n').count(), 8);
        assert!(first == second, "{preset}: two runs with seed 42 differ");
    }
}

#[test]
fn different_seeds_give_different_files() {
    for preset in Preset::ALL {
        let a = dataset(preset, 1, 4);
        let b = dataset(preset, 2, 4);
        assert_ne!(a, b, "{preset}: seeds 1 and 2 gave the same file");
        // Not just the names: no scene of one file appears in the other.
        let lines = |d: &[u8]| -> Vec<String> {
            String::from_utf8(d.to_vec())
                .unwrap()
                .lines()
                .map(|l| l.split_once(",\"robot\"").unwrap().1.to_owned())
                .collect()
        };
        let (la, lb) = (lines(&a), lines(&b));
        assert!(
            la.iter().all(|l| !lb.contains(l)),
            "{preset}: a scene repeats"
        );
    }
}

#[test]
fn a_shorter_run_is_a_prefix_of_a_longer_one() {
    let short = dataset(Preset::Moi, 9, 3);
    let long = dataset(Preset::Moi, 9, 6);
    assert!(long.len() > short.len());
    assert!(long.starts_with(&short));
}

#[test]
fn scenes_within_a_run_differ() {
    let generator = Generator::new(Preset::Mrc.config(), 5).unwrap();
    let a = generator.scene(0).unwrap();
    let b = generator.scene(1).unwrap();
    assert_ne!(a.objects, b.objects);
    assert_eq!(a.pair.name, "sim-5-0");
    assert_eq!(b.pair.name, "sim-5-1");
}

#[test]
fn up_vectors_are_the_cameras_vertical_and_change_nothing_else() {
    use nalgebra::Vector3;
    for preset in Preset::ALL {
        let plain = Generator::new(preset.config(), 7).unwrap();
        let exact = plain.clone().with_up_vectors(0.0).unwrap();
        let tilted = plain.clone().with_up_vectors(2.0).unwrap();
        for k in 0..4 {
            let (a, b, c) = (
                plain.scene(k).unwrap(),
                exact.scene(k).unwrap(),
                tilted.scene(k).unwrap(),
            );
            assert_eq!(a.pair.robot.objects(), b.pair.robot.objects());
            assert_eq!(a.pair.human.objects(), c.pair.human.objects());
            assert_eq!(a.pair.robot.up(), None);
            for (view, exact_up, tilted_up) in [
                (&b.robot, b.pair.robot.up(), c.pair.robot.up()),
                (&b.human, b.pair.human.up(), c.pair.human.up()),
            ] {
                let vertical = view.camera.direction_to_camera(&Vector3::z());
                assert!((exact_up.unwrap() - vertical).norm() < 1e-12);
                // Within five standard deviations of a 2-degree tilt.
                let angle = tilted_up.unwrap().angle(&vertical).to_degrees();
                assert!(angle < 10.0, "{preset} scene {k}: tilted {angle} degrees");
            }
        }
    }
    assert!(
        Generator::new(Preset::Moi.config(), 1)
            .unwrap()
            .with_up_vectors(f64::NAN)
            .is_err()
    );
}
