//! The counter sees an allocation, and only the enabling thread's.

#[global_allocator]
static ALLOCATOR: vref_alloc_count::Counting = vref_alloc_count::Counting;

#[test]
fn an_allocation_is_counted_and_none_is_counted_without_one() {
    let (v, n) = vref_alloc_count::allocations_in(|| vec![1u8; 64]);
    assert_eq!(v.len(), 64);
    assert!(n >= 1, "{n}");
    let (_, n) = vref_alloc_count::allocations_in(|| 2 + 2);
    assert_eq!(n, 0);
}

#[test]
fn another_threads_allocations_are_not_counted() {
    use std::sync::atomic::{AtomicU8, Ordering};
    use std::time::Duration;
    // 0: wait, 1: allocate now, 2: allocated. Atomics, so that this
    // thread allocates nothing while it hands over.
    static STEP: AtomicU8 = AtomicU8::new(0);
    let worker = std::thread::spawn(|| {
        while STEP.load(Ordering::Acquire) == 0 {
            std::thread::sleep(Duration::from_millis(1));
        }
        let v = vec![0u64; 1024];
        STEP.store(2, Ordering::Release);
        v.len()
    });
    let (_, n) = vref_alloc_count::allocations_in(|| {
        STEP.store(1, Ordering::Release);
        while STEP.load(Ordering::Acquire) != 2 {
            std::thread::sleep(Duration::from_millis(1));
        }
    });
    assert_eq!(n, 0, "the worker's allocation was counted here");
    assert_eq!(worker.join().ok(), Some(1024));
}

#[test]
fn a_count_inside_another_is_part_of_it() {
    let ((_, inner), outer) = vref_alloc_count::allocations_in(|| {
        let v = vec![1u8; 16];
        let counted = vref_alloc_count::allocations_in(|| vec![2u8; 16]);
        drop(v);
        counted
    });
    assert!(inner >= 1, "{inner}");
    assert!(outer > inner, "outer {outer}, inner {inner}");
}
