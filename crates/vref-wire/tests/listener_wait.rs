//! iceoryx2 0.10's listener takes a timeout under a microsecond as none
//! and blocks until notified; `listener_timeout` is what every vref wait
//! on a listener goes through. A notifier in another thread wakes a wait
//! that blocks, after 2 s, so that this test fails instead of hanging.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use iceoryx2::prelude::*;
use vref_wire::ipc::{IpcSettings, SHORTEST_LISTENER_WAIT, create_node, listener_timeout};

const WAKE_AFTER: Duration = Duration::from_secs(2);

/// Each test's own root path and prefix (shared memory is named by it).
fn settings(root: &std::path::Path, tag: &str) -> IpcSettings {
    IpcSettings {
        root_path: Some(root.to_owned()),
        prefix: format!("lw{}{tag}_", std::process::id()),
        ..IpcSettings::default()
    }
}

/// How long a listener's `timed_wait(wait)` takes with nobody notifying
/// (`WAKE_AFTER` or more when it blocked).
fn waited(settings: &IpcSettings, wait: Duration) -> Duration {
    let name: ServiceName = "vref/test/listener-wait".try_into().unwrap();
    let node = create_node(settings, "listener").unwrap();
    let event = node
        .service_builder(&name)
        .event()
        .open_or_create()
        .unwrap();
    let listener = event.listener_builder().create().unwrap();
    let done = AtomicBool::new(false);
    std::thread::scope(|s| {
        s.spawn(|| {
            let node = create_node(settings, "waker").unwrap();
            let event = node
                .service_builder(&name)
                .event()
                .open_or_create()
                .unwrap();
            let notifier = event.notifier_builder().create().unwrap();
            let start = Instant::now();
            while start.elapsed() < WAKE_AFTER {
                if done.load(Ordering::SeqCst) {
                    return;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
            notifier.notify().unwrap();
        });
        let start = Instant::now();
        listener.timed_wait(|_| {}, wait).unwrap();
        done.store(true, Ordering::SeqCst);
        start.elapsed()
    })
}

#[test]
fn a_wait_shorter_than_a_microsecond_returns_once_made_the_shortest() {
    let root = tempfile::tempdir().unwrap();
    let settings = settings(root.path(), "guard");
    for wait in [
        Duration::ZERO,
        Duration::from_nanos(500),
        Duration::from_nanos(999),
    ] {
        let took = waited(&settings, listener_timeout(wait));
        assert!(
            took < WAKE_AFTER,
            "{wait:?} as {SHORTEST_LISTENER_WAIT:?}: {took:?}"
        );
    }
}

/// What the guard is for: if iceoryx2 stops blocking on these, this fails
/// and the guard can go.
#[test]
fn iceoryx2_blocks_on_a_wait_shorter_than_a_microsecond() {
    let root = tempfile::tempdir().unwrap();
    let took = waited(&settings(root.path(), "bare"), Duration::from_nanos(500));
    assert!(took >= WAKE_AFTER, "{took:?}");
}
