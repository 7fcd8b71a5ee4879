//! The segmenter makes no heap allocation per frame once its buffers have
//! grown to the frame: a counting allocator checks it on a real frame.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use vref_perception::*;

#[global_allocator]
static ALLOCATOR: vref_alloc_count::Counting = vref_alloc_count::Counting;

#[test]
fn frames_after_the_first_allocate_nothing() {
    let scene = vref_testkit::data("osd/learn/learn21");
    assert!(
        scene.is_dir(),
        "the OSD data set is missing: {}",
        scene.display()
    );
    let images = folder::RgbdImages::load(&scene, ImageLimit::default()).unwrap();
    let frame = RgbdFrame {
        colour: &images.colour,
        depth: &images.depth,
        intrinsics: images.camera.intrinsics,
        up: None,
    };
    let mut segmenter = Segmenter::new(SegmentationSettings::default());
    let mut labels = LabelImage::new(1, 1);
    let (first, growing) =
        vref_alloc_count::allocations_in(|| segmenter.segment(&frame, &mut labels));
    assert!(first.unwrap().objects() > 0);
    assert!(growing > 0, "the first frame grows the buffers");
    let capacity = segmenter.buffer_capacity();
    for _ in 0..3 {
        let (result, count) =
            vref_alloc_count::allocations_in(|| segmenter.segment(&frame, &mut labels));
        result.unwrap();
        assert_eq!(count, 0, "a frame after the first allocated");
    }
    assert_eq!(segmenter.buffer_capacity(), capacity);
}
