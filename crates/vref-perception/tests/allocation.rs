//! The front end makes no heap allocation per frame once its buffers have
//! grown to the frame's masks: a counting allocator checks it.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{Disc, draw, intrinsics, two_tone, yellow};
use vref_perception::{Frame, FrontEnd, Mask, PerceptionSettings};

#[global_allocator]
static ALLOCATOR: vref_alloc_count::Counting = vref_alloc_count::Counting;

#[test]
fn frames_after_the_first_allocate_nothing() {
    let discs: Vec<Disc> = (0..16)
        .map(|k| Disc {
            centre: (
                40.0 + 75.0 * f64::from(k % 8),
                120.0 + 220.0 * f64::from(k / 8),
            ),
            radius: 10.0 + 2.0 * f64::from(k),
            depth: 0.6 + 0.05 * f64::from(k),
            look: if k % 2 == 0 { yellow } else { two_tone },
        })
        .collect();
    let (colour, depth, masks) = draw(&discs, 2.5);
    let masks: Vec<Mask<'_>> = masks
        .iter()
        .enumerate()
        .map(|(k, m)| Mask {
            id: k as u64,
            pixels: m,
        })
        .collect();
    let frame = Frame {
        colour: &colour,
        depth: &depth,
        intrinsics: intrinsics(),
        masks: &masks,
    };
    let mut front_end = FrontEnd::new(PerceptionSettings::default().human());
    let mut out = Vec::new();
    let (first, growing) = vref_alloc_count::allocations_in(|| front_end.process(&frame, &mut out));
    assert_eq!(first.unwrap().too_small, 0);
    assert!(growing > 0, "the first frame grows the buffers");
    let capacity = (front_end.buffer_capacity(), out.capacity());
    for _ in 0..5 {
        let (result, count) =
            vref_alloc_count::allocations_in(|| front_end.process(&frame, &mut out));
        result.unwrap();
        assert_eq!(count, 0, "a frame after the first allocated");
    }
    assert_eq!(out.len(), 16);
    assert_eq!((front_end.buffer_capacity(), out.capacity()), capacity);
}
