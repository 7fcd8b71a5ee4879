//! The front end makes no heap allocation per frame once its buffers have
//! grown to the frame's masks: a counting allocator checks it.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{Disc, draw, intrinsics, two_tone, yellow};
use vref_perception::{Frame, FrontEnd, Mask, PerceptionSettings};

mod counting {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;
    use std::sync::atomic::{AtomicUsize, Ordering};

    pub struct Counting;

    static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

    thread_local! {
        static ENABLED: Cell<bool> = const { Cell::new(false) };
    }

    fn note() {
        // `try_with`: the allocator may run while thread locals are torn down.
        if ENABLED.try_with(Cell::get).unwrap_or(false) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
    }

    // SAFETY: every call is passed on unchanged to the system allocator;
    // the counter neither allocates nor touches the memory.
    #[allow(unsafe_code)]
    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
            note();
            // SAFETY: the caller's contract is System's contract.
            unsafe { System.alloc(layout) }
        }
        unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
            note();
            // SAFETY: as above.
            unsafe { System.alloc_zeroed(layout) }
        }
        unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
            note();
            // SAFETY: as above.
            unsafe { System.realloc(ptr, layout, new_size) }
        }
        unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
            // SAFETY: as above.
            unsafe { System.dealloc(ptr, layout) }
        }
    }

    /// Allocations made by this thread while `f` ran.
    pub fn allocations_in<T>(f: impl FnOnce() -> T) -> (T, usize) {
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        ENABLED.with(|e| e.set(true));
        let value = f();
        ENABLED.with(|e| e.set(false));
        (value, ALLOCATIONS.load(Ordering::Relaxed) - before)
    }
}

#[global_allocator]
static ALLOCATOR: counting::Counting = counting::Counting;

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
    let (first, growing) = counting::allocations_in(|| front_end.process(&frame, &mut out));
    assert_eq!(first.unwrap().too_small, 0);
    assert!(growing > 0, "the first frame grows the buffers");
    let capacity = (front_end.buffer_capacity(), out.capacity());
    for _ in 0..5 {
        let (result, count) = counting::allocations_in(|| front_end.process(&frame, &mut out));
        result.unwrap();
        assert_eq!(count, 0, "a frame after the first allocated");
    }
    assert_eq!(out.len(), 16);
    assert_eq!((front_end.buffer_capacity(), out.capacity()), capacity);
}
