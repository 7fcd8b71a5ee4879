//! iceoryx2 0.10's listener takes a timeout under a microsecond as none
//! and blocks until notified; `listener_timeout` is what every vref wait
//! on a listener goes through. A notifier in another thread wakes a wait
//! still blocked after 2 s (a bound, so that this test fails instead of
//! hanging) and says that it had to.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use iceoryx2::prelude::*;
use vref_wire::ipc::{
    EventPort, IpcSettings, Node, SHORTEST_LISTENER_WAIT, create_node, listener_timeout,
};

const WAKE_AFTER: Duration = Duration::from_secs(2);

/// Each test's own root path and prefix (shared memory is named by it).
fn settings(root: &std::path::Path, tag: &str) -> IpcSettings {
    IpcSettings {
        root_path: Some(root.to_owned()),
        prefix: format!("lw{}{tag}_", std::process::id()),
        ..IpcSettings::default()
    }
}

/// The test's event service, opened by a node of its own.
fn event(settings: &IpcSettings, node_name: &str) -> (Node, EventPort) {
    let node = create_node(settings, node_name).unwrap();
    let name: ServiceName = "vref/test/listener-wait".try_into().unwrap();
    let event = node
        .service_builder(&name)
        .event()
        .open_or_create()
        .unwrap();
    (node, event)
}

/// Whether a listener's `timed_wait(wait)`, with nobody else notifying,
/// only returned because the waker notified it.
fn needed_waking(settings: &IpcSettings, wait: Duration) -> bool {
    let (_node, listening) = event(settings, "listener");
    let listener = listening.listener_builder().create().unwrap();
    let (done, woke) = (AtomicBool::new(false), AtomicBool::new(false));
    std::thread::scope(|s| {
        s.spawn(|| {
            let (_node, waking) = event(settings, "waker");
            let notifier = waking.notifier_builder().create().unwrap();
            let start = Instant::now();
            while start.elapsed() < WAKE_AFTER {
                if done.load(Ordering::SeqCst) {
                    return;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
            woke.store(true, Ordering::SeqCst);
            notifier.notify().unwrap();
        });
        listener.timed_wait(|_| {}, wait).unwrap();
        done.store(true, Ordering::SeqCst);
    });
    woke.load(Ordering::SeqCst)
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
        assert!(
            !needed_waking(&settings, listener_timeout(wait)),
            "{wait:?} as {SHORTEST_LISTENER_WAIT:?} blocked"
        );
    }
}

/// What the guard is for: if iceoryx2 stops blocking on these, this fails
/// and the guard can go.
#[test]
fn iceoryx2_blocks_on_a_wait_shorter_than_a_microsecond() {
    let root = tempfile::tempdir().unwrap();
    assert!(needed_waking(
        &settings(root.path(), "bare"),
        Duration::from_nanos(500)
    ));
}
