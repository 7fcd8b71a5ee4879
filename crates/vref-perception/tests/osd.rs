//! The segmenter on real Kinect scenes: the OSD learn scenes held aside
//! from tuning (number 0 mod 5), scored by PROVENANCE.md's protocol. The
//! floors are about 0.02 under what these scenes measured when the
//! defaults were set (docs/perception.md, "Segmenter").
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::PathBuf;

use vref_perception::segment::score::{ImageScore, MeanScore, score_image};
use vref_perception::*;

fn osd() -> PathBuf {
    let dir = vref_testkit::data("osd");
    assert!(
        dir.join("learn").is_dir(),
        "the OSD data set is missing: expected {} (../shared/data/osd beside the repository, or VREF_DATA)",
        dir.display()
    );
    dir
}

#[test]
fn held_aside_osd_scenes_score_above_their_floors() {
    let dir = osd();
    let mut segmenter = Segmenter::new(SegmentationSettings::default());
    let mut labels = LabelImage::new(1, 1);
    let mut scores: Vec<ImageScore> = Vec::new();
    for n in (0..45).step_by(5) {
        let scene = dir.join(format!("learn/learn{n}"));
        // The scene's labels load as its masks, through the camera file
        // beside learn/ (the loader the feeds and `vref segment` use).
        let images = folder::RgbdImages::load_files(
            &scene.join("rgb.png"),
            &scene.join("depth.png"),
            Some(&scene.join("label.png")),
            folder::Camera::load(&folder::camera_file_of(&scene).unwrap()).unwrap(),
            ImageLimit::default(),
        )
        .unwrap();
        let truth = images.masks.unwrap();
        let frame = RgbdFrame {
            colour: &images.colour,
            depth: &images.depth,
            intrinsics: images.camera.intrinsics,
            up: None,
        };
        let result = segmenter.segment(&frame, &mut labels).unwrap();
        assert!(
            matches!(result, Segmentation::Objects { .. }),
            "learn{n}: {result:?}"
        );
        let s = score_image(&labels, &truth, 640, 480, 20).unwrap();
        assert!(s.overlap.f > 0.85, "learn{n}: overlap F {:.3}", s.overlap.f);
        scores.push(s);
    }
    let mean = MeanScore::of(&scores);
    assert_eq!(mean.images, 9);
    assert!(mean.overlap.f >= 0.96, "overlap F {:.3}", mean.overlap.f);
    assert!(
        mean.boundary.f >= 0.935,
        "boundary F {:.3}",
        mean.boundary.f
    );
    assert!(mean.p75 >= 0.94, "%75 {:.3}", mean.p75);
}
