//! The BOP importer on copies of the shared scenes, intact and broken.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::fs;
use std::path::{Path, PathBuf};

use vref_import::{BopDataset, BopImport, BopOptions, BopScene, ImportError};
use vref_perception::PerceptionSettings;

fn shared() -> PathBuf {
    vref_testkit::data("bop")
}

fn options() -> BopOptions {
    BopOptions {
        robot_image: 0,
        human_image: 1,
        perception: PerceptionSettings::default(),
        world_up: None,
    }
}

fn copy_dir(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for entry in fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.path().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            fs::copy(entry.path(), &target).unwrap();
            let mut permissions = fs::metadata(&target).unwrap().permissions();
            #[allow(clippy::permissions_set_readonly_false)]
            permissions.set_readonly(false);
            fs::set_permissions(&target, permissions).unwrap();
        }
    }
}

/// A dataset folder `table` with shared scenes 0 and 1.
fn two_scenes() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let dataset = dir.path().join("table");
    for scene in ["000000", "000001"] {
        copy_dir(
            &shared().join("table/test").join(scene),
            &dataset.join("test").join(scene),
        );
    }
    (dir, dataset)
}

/// Imports with scene 0 broken by `breaking`: scene 1 is still imported,
/// and scene 0's error is returned as printed.
fn broken(breaking: impl Fn(&Path)) -> String {
    let (_dir, dataset) = two_scenes();
    breaking(&dataset.join("test/000000"));
    let import = BopImport::run(&BopDataset::open(&dataset, "test").unwrap(), &options());
    let names: Vec<&str> = import.scenes.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["table/000001"]);
    assert_eq!(import.failed.len(), 1);
    let (scene, error) = &import.failed[0];
    assert_eq!(scene, "table/000000");
    chain(error)
}

fn chain(err: &dyn std::error::Error) -> String {
    let mut text = err.to_string();
    let mut source = err.source();
    while let Some(e) = source {
        text = format!("{text}: {e}");
        source = e.source();
    }
    text
}

fn write_png_gray8(path: &Path, w: u32, h: u32) {
    image::GrayImage::new(w, h).save(path).unwrap();
}

#[test]
fn scenes_are_named_by_folder_and_id_with_distinct_ids_and_one_to_one_truth() {
    let (_dir, dataset) = two_scenes();
    let dataset = BopDataset::open(&dataset, "test").unwrap();
    let scene = BopScene::measure(&dataset, &dataset.scenes()[0], &options()).unwrap();
    assert_eq!(scene.name, "table/000000");
    let pair = scene.pair(&vref_scene::Limits::default()).unwrap();
    let robot: Vec<u64> = pair.robot.objects().iter().map(|o| o.id).collect();
    let human: Vec<u64> = pair.human.objects().iter().map(|o| o.id).collect();
    assert!(robot.iter().all(|id| !human.contains(id)));
    // Every true pair is one instance seen in both views.
    for (h, r) in &pair.ground_truth {
        let hk = scene.human.instances[human.iter().position(|x| x == h).unwrap()];
        let rk = scene.robot.instances[robot.iter().position(|x| x == r).unwrap()];
        assert_eq!(hk, rk);
    }
    assert!(!pair.ground_truth.is_empty());
    // Stated errors: positive, the headset's larger than the robot's.
    let along = |o: &vref_scene::SceneObject| o.position_sigma.iter().map(|s| s * s).sum::<f64>();
    assert!(pair.robot.objects().iter().all(|o| along(o) > 0.0));
    let mean = |g: &vref_scene::SceneGraph| {
        g.objects()
            .iter()
            .map(|o| along(o).sqrt() / o.position.coords.norm())
            .sum::<f64>()
            / g.len() as f64
    };
    assert!(mean(&pair.human) > 5.0 * mean(&pair.robot));
}

#[test]
fn a_missing_file_is_named() {
    let message = broken(|scene| fs::remove_file(scene.join("depth/000001.png")).unwrap());
    assert!(message.contains("depth/000001.png"), "{message}");
}

#[test]
fn a_depth_image_that_is_not_16_bit_is_named() {
    let message = broken(|scene| write_png_gray8(&scene.join("depth/000000.png"), 640, 480));
    assert!(
        message.contains("depth/000000.png") && message.contains("16-bit"),
        "{message}"
    );
}

#[test]
fn an_image_of_another_size_is_named() {
    let message = broken(|scene| {
        let depth = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::new(320, 240);
        depth.save(scene.join("depth/000000.png")).unwrap();
    });
    assert!(
        message.contains("depth/000000.png") && message.contains("320x240"),
        "{message}"
    );
}

#[test]
fn a_mask_of_another_size_is_named() {
    let message = broken(|scene| {
        write_png_gray8(&scene.join("mask_visib/000001_000003.png"), 640, 479);
    });
    assert!(
        message.contains("mask_visib/000001_000003.png") && message.contains("640x479"),
        "{message}"
    );
}

#[test]
fn intrinsics_that_are_not_finite_and_positive_are_named() {
    let message = broken(|scene| {
        let path = scene.join("scene_camera.json");
        let text = fs::read_to_string(&path).unwrap();
        let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
        json["0"]["cam_K"][0] = serde_json::json!(-539.0);
        fs::write(&path, json.to_string()).unwrap();
    });
    assert!(
        message.contains("scene_camera.json") && message.contains("fx is -539"),
        "{message}"
    );
}

#[test]
fn a_dataset_without_scenes_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    fs::create_dir_all(dir.path().join("test")).unwrap();
    let err = BopDataset::open(dir.path(), "test").unwrap_err();
    assert!(matches!(err, ImportError::NoScenes { .. }), "{err}");
    let err = BopDataset::open(dir.path(), "val").unwrap_err();
    assert!(chain(&err).contains("val"), "{err}");
}

#[test]
fn with_the_worlds_up_each_view_carries_its_cameras_up_vector() {
    let (_dir, dataset) = two_scenes();
    let data = BopDataset::open(&dataset, "test").unwrap();
    let scene = &data.scenes()[0];
    let limits = vref_scene::Limits::default();
    let plain = BopScene::measure(&data, scene, &options()).unwrap();
    assert_eq!(plain.pair(&limits).unwrap().robot.up(), None);
    let upright = BopOptions {
        world_up: Some([0.0, 0.0, 2.0]),
        ..options()
    };
    let measured = BopScene::measure(&data, scene, &upright).unwrap();
    let pair = measured.pair(&limits).unwrap();
    // The third column of each image's cam_R_w2c (the world's z).
    let cameras: serde_json::Value = serde_json::from_str(
        &fs::read_to_string(dataset.join("test/000000/scene_camera.json")).unwrap(),
    )
    .unwrap();
    for (image, up) in [("0", pair.robot.up()), ("1", pair.human.up())] {
        let r = &cameras[image]["cam_R_w2c"];
        let column = [2, 5, 8].map(|k| r[k].as_f64().unwrap());
        let up = up.unwrap();
        for (a, b) in [up.x, up.y, up.z].iter().zip(column) {
            assert!(
                (a - b).abs() < 1e-9,
                "image {image}: {up:?} against {column:?}"
            );
        }
    }
    // The objects are measured as without it.
    assert_eq!(plain.robot.detections, measured.robot.detections);
    assert_eq!(measured.missing_up(), None);
    // Without cam_R_w2c a view has no up vector, and the warning says why
    // and names the scene.
    let path = dataset.join("test/000000/scene_camera.json");
    let mut json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    for camera in json.as_object_mut().unwrap().values_mut() {
        camera.as_object_mut().unwrap().remove("cam_R_w2c");
    }
    fs::write(&path, json.to_string()).unwrap();
    let data = BopDataset::open(&dataset, "test").unwrap();
    let poseless = BopScene::measure(&data, &data.scenes()[0], &upright).unwrap();
    let warning = poseless.missing_up().unwrap();
    assert!(
        warning.contains(&poseless.name) && warning.contains("cam_R_w2c"),
        "{warning}"
    );
}
