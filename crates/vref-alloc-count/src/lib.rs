//! Counts heap allocations made by the thread that enabled counting, so a
//! test can check that a path (the query path, a frame of the perception
//! front end) allocates nothing while the test harness's other threads
//! allocate as they like.
//!
//! A test binary installs it with
//!
//! ```ignore
//! #[global_allocator]
//! static ALLOCATOR: vref_alloc_count::Counting = vref_alloc_count::Counting;
//! ```
//!
//! and measures with [`allocations_in`].

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// The system allocator, counting the calls of threads that enabled it.
#[derive(Debug)]
pub struct Counting;

thread_local! {
    // Per thread, not one shared counter: the test harness runs tests on
    // threads of their own at once, and one test's allocations must not
    // land in another's count. `None`: this thread is not counting.
    static ALLOCATIONS: Cell<Option<usize>> = const { Cell::new(None) };
}

fn note() {
    // `try_with`: the allocator may run while thread locals are torn down.
    let _ = ALLOCATIONS.try_with(|count| {
        if let Some(n) = count.get() {
            count.set(Some(n + 1));
        }
    });
}

// SAFETY: every call is passed on unchanged to the system allocator; the
// counter neither allocates nor touches the memory.
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

/// `f`'s value and the allocations this thread made while it ran (counted
/// only where [`Counting`] is the global allocator).
pub fn allocations_in<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let outer = ALLOCATIONS.with(|count| count.replace(Some(0)));
    let value = f();
    let n = ALLOCATIONS.with(|count| count.replace(outer)).unwrap_or(0);
    // A count around this one counts these too.
    if let Some(m) = outer {
        ALLOCATIONS.with(|count| count.set(Some(m + n)));
    }
    (value, n)
}
