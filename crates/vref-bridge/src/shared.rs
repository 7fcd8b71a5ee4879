//! What the bridge's threads share. iceoryx2 ports stay on the thread
//! that made them; Zenoh calls back on its own threads, so what those
//! callbacks touch (the intake and the counters) sits behind mutexes held
//! only for a check or an increment.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::Duration;

use vref_config::Config;

use crate::intake::{HeadsetIntake, IntakeLimits, QueryIntake};
use crate::keys::Keys;
use crate::stats::{BridgeStats, Published};

/// Longest a thread waits before looking at the stop flag again.
pub(crate) const POLL: Duration = Duration::from_millis(100);

/// What the threads share.
#[derive(Debug)]
pub(crate) struct Shared {
    pub config: Config,
    pub keys: Keys,
    /// The session the bridge publishes headset messages under.
    pub session: u64,
    pub started_ns: u64,
    stop: AtomicBool,
    pub intake: Mutex<HeadsetIntake>,
    pub queries: Mutex<QueryIntake>,
    pub published: Mutex<Published>,
}

impl Shared {
    pub fn new(config: &Config, keys: Keys, session: u64, started_ns: u64) -> Self {
        let settings = &config.bridge;
        Self {
            config: config.clone(),
            keys,
            session,
            started_ns,
            stop: AtomicBool::new(false),
            intake: Mutex::new(HeadsetIntake::new(intake_limits(config), session)),
            queries: Mutex::new(QueryIntake::new(
                settings.max_message_bytes,
                settings.max_query_rate_hz,
            )),
            published: Mutex::new(Published::default()),
        }
    }

    pub fn stopping(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// Asks every thread to stop; each notices within [`POLL`].
    pub fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
    }

    /// Every counter, as taken at `taken_ns`.
    pub fn stats(&self, taken_ns: u64) -> BridgeStats {
        // One lock at a time: each guard is dropped before the next is taken.
        let (human_snapshot, human_gesture) = {
            let intake = lock(&self.intake);
            (
                intake.snapshot_counters().clone(),
                intake.ray_counters().clone(),
            )
        };
        let reference = lock(&self.queries).counters().clone();
        let published = lock(&self.published).clone();
        BridgeStats {
            started_ns: self.started_ns,
            taken_ns,
            pid: std::process::id(),
            prefix: self.keys.prefix().to_owned(),
            session: self.session,
            human_snapshot,
            human_gesture,
            reference,
            published,
        }
    }
}

/// What the headset intake lets in, from `[scene]` and `[bridge]`.
pub(crate) fn intake_limits(config: &Config) -> IntakeLimits {
    let settings = &config.bridge;
    IntakeLimits {
        scene: config.scene.limits(),
        max_message_bytes: settings.max_message_bytes,
        max_snapshot_rate_hz: settings.max_snapshot_rate_hz,
        max_gesture_rate_hz: settings.max_gesture_rate_hz,
        session_takeover: Duration::from_millis(settings.session_takeover_ms),
    }
}

/// A mutex's value even if a thread panicked holding it: counters and
/// checks stay usable (they hold no invariant a panic could break half-way).
pub(crate) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

#[cfg(test)]
mod tests {
    use std::time::Instant;

    use super::*;

    fn shared(config: &Config) -> Shared {
        let keys = Keys::new(&config.bridge.prefix).unwrap_or_else(|e| panic!("{e}"));
        Shared::new(config, keys, 77, 1_000)
    }

    #[test]
    fn the_intake_limits_are_the_configured_ones() {
        let mut config = Config::default();
        config.bridge.max_message_bytes = 4096;
        config.bridge.max_snapshot_rate_hz = 12.5;
        config.bridge.max_gesture_rate_hz = 7.0;
        config.bridge.session_takeover_ms = 250;
        config.scene.capacity = 9;
        let limits = intake_limits(&config);
        assert_eq!(limits.max_message_bytes, 4096);
        assert_eq!(limits.max_snapshot_rate_hz, 12.5);
        assert_eq!(limits.max_gesture_rate_hz, 7.0);
        assert_eq!(limits.session_takeover, Duration::from_millis(250));
        assert_eq!(limits.scene, config.scene.limits());
    }

    #[test]
    fn statistics_carry_every_counter_and_who_took_them() {
        let shared = shared(&Config::default());
        let now = Instant::now();
        // Refused before decoding: an encoding the bridge does not speak.
        let refused = lock(&shared.intake).snapshot("text/plain", b"hello", now, 5);
        assert!(refused.is_err());
        let query = lock(&shared.queries).query(Some("text/plain"), Some(b"{}"), now);
        assert!(query.is_err());
        lock(&shared.published).robot_snapshot += 3;
        lock(&shared.intake).ray_counters_mut().refuse("busy");

        let stats = shared.stats(2_000);
        assert_eq!((stats.started_ns, stats.taken_ns), (1_000, 2_000));
        assert_eq!(stats.session, 77);
        assert_eq!(stats.pid, std::process::id());
        assert_eq!(stats.prefix, Config::default().bridge.prefix);
        assert_eq!(stats.human_snapshot.received, 1);
        assert_eq!(stats.human_snapshot.refused.get("encoding"), Some(&1));
        assert_eq!(stats.human_gesture.refused.get("busy"), Some(&1));
        assert_eq!(stats.reference.refused.get("encoding"), Some(&1));
        assert_eq!(stats.published.robot_snapshot, 3);
    }

    #[test]
    fn a_stop_is_seen_by_every_holder() {
        let shared = std::sync::Arc::new(shared(&Config::default()));
        assert!(!shared.stopping());
        let other = std::sync::Arc::clone(&shared);
        other.stop();
        assert!(shared.stopping());
    }

    #[test]
    fn a_poisoned_mutex_still_gives_its_counters() {
        let published = std::sync::Arc::new(Mutex::new(Published::default()));
        let held = std::sync::Arc::clone(&published);
        let panicked = std::thread::spawn(move || {
            let mut guard = lock(&held);
            guard.failed += 1;
            panic!("while holding the counters");
        })
        .join();
        assert!(panicked.is_err());
        assert!(published.is_poisoned());
        assert_eq!(lock(&published).failed, 1);
    }
}
