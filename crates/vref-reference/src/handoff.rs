//! How the matcher's threads pass work without waiting on each other: the
//! intake posts the newest pair of snapshots to the solver, replacing one
//! not yet taken (so solves coalesce to the newest pair), and the solver
//! publishes each finished solution for the query path to pick up. Each
//! lock is held for a pointer swap, never during a solve.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::time::Duration;

/// One pending item, replaced by a newer one until taken.
#[derive(Debug)]
pub struct Mailbox<T> {
    slot: Mutex<Slot<T>>,
    ready: Condvar,
}

#[derive(Debug)]
struct Slot<T> {
    item: Option<T>,
    closed: bool,
    /// Items replaced before they were taken.
    coalesced: u64,
}

impl<T> Default for Mailbox<T> {
    fn default() -> Self {
        Self {
            slot: Mutex::new(Slot {
                item: None,
                closed: false,
                coalesced: 0,
            }),
            ready: Condvar::new(),
        }
    }
}

impl<T> Mailbox<T> {
    /// Leaves `item` for the taker, in place of any not yet taken.
    pub fn post(&self, item: T) {
        let mut slot = self.lock();
        if slot.item.replace(item).is_some() {
            slot.coalesced += 1;
        }
        drop(slot);
        self.ready.notify_one();
    }

    /// Waits for an item; `None` once closed.
    pub fn take(&self) -> Option<T> {
        let mut slot = self.lock();
        loop {
            if slot.closed {
                return None;
            }
            if let Some(item) = slot.item.take() {
                return Some(item);
            }
            slot = self
                .ready
                .wait(slot)
                .unwrap_or_else(PoisonError::into_inner);
        }
    }

    /// Like [`Mailbox::take`], giving up after `limit` (for tests).
    pub fn take_within(&self, limit: Duration) -> Option<T> {
        let slot = self.lock();
        let (mut slot, _) = self
            .ready
            .wait_timeout_while(slot, limit, |s| s.item.is_none() && !s.closed)
            .unwrap_or_else(PoisonError::into_inner);
        if slot.closed { None } else { slot.item.take() }
    }

    /// Wakes the taker for good: it gets `None` from now on.
    pub fn close(&self) {
        self.lock().closed = true;
        self.ready.notify_all();
    }

    /// Items replaced before they were taken, so far.
    pub fn coalesced(&self) -> u64 {
        self.lock().coalesced
    }

    fn lock(&self) -> MutexGuard<'_, Slot<T>> {
        // A panic while holding the lock leaves a slot that is still whole.
        self.slot.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// The newest value published, with a version that the reader compares
/// without taking the lock.
#[derive(Debug)]
pub struct Latest<T> {
    value: Mutex<Option<Arc<T>>>,
    version: AtomicU64,
}

impl<T> Default for Latest<T> {
    fn default() -> Self {
        Self {
            value: Mutex::new(None),
            version: AtomicU64::new(0),
        }
    }
}

impl<T> Latest<T> {
    pub fn publish(&self, value: Arc<T>) {
        let mut held = self.value.lock().unwrap_or_else(PoisonError::into_inner);
        *held = Some(value);
        self.version.fetch_add(1, Ordering::Release);
    }

    /// The value if one newer than version `seen` was published, with its
    /// version. Makes no allocation.
    pub fn newer_than(&self, seen: u64) -> Option<(u64, Arc<T>)> {
        if self.version.load(Ordering::Acquire) == seen {
            return None;
        }
        let held = self.value.lock().unwrap_or_else(PoisonError::into_inner);
        let version = self.version.load(Ordering::Acquire);
        held.clone().map(|v| (version, v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mailbox_keeps_only_the_newest_item() {
        let mailbox = Mailbox::default();
        mailbox.post(1);
        mailbox.post(2);
        mailbox.post(3);
        assert_eq!(mailbox.take(), Some(3));
        assert_eq!(mailbox.coalesced(), 2);
        assert_eq!(mailbox.take_within(Duration::from_millis(10)), None);
    }

    #[test]
    fn a_closed_mailbox_wakes_its_taker() {
        let mailbox = Arc::new(Mailbox::<u32>::default());
        let taker = {
            let mailbox = mailbox.clone();
            std::thread::spawn(move || mailbox.take())
        };
        std::thread::sleep(Duration::from_millis(20));
        mailbox.close();
        assert_eq!(taker.join().ok(), Some(None));
    }

    #[test]
    fn latest_is_read_once_per_version() {
        let latest = Latest::default();
        assert!(latest.newer_than(0).is_none());
        latest.publish(Arc::new("a"));
        let (v, value) = latest.newer_than(0).unwrap_or((0, Arc::new("")));
        assert_eq!((v, *value), (1, "a"));
        assert!(latest.newer_than(v).is_none());
    }
}
