//! Which messages of one service come after which: the rules that keep one
//! message from locking a feed out.
//!
//! 1. Order is kept per publisher port (iceoryx2's port id, which the
//!    sample header carries): another port's messages, whatever session
//!    and sequence they claim, never move a feed's sequence.
//! 2. A port may start a new session (a bridge forwarding a restarted
//!    headset); its sequence starts again.
//! 3. Within a port's session the sequence must grow, and by no more than
//!    the port could have counted since its last accepted message
//!    ([`MAX_JUMP`] plus [`MAX_RATE_PER_MS`] per millisecond).
//! 4. A port whose messages have all been refused as out of order for
//!    `resync_after` is taken again from its next message: whatever went
//!    wrong, a stalled feed recovers on its own.

use std::time::{Duration, Instant};

use crate::{RejectReason, Rejected};

/// Ports remembered per service: iceoryx2 allows four publishers per
/// vref service (services.rs), twice that leaves room for dead ones.
const PORTS: usize = 8;
/// Sequence numbers a port may skip at any time (messages it published
/// that this side never read: latest wins).
pub const MAX_JUMP: u64 = 1000;
/// ... plus this many per millisecond since its last accepted message:
/// 20 kHz, twice the fastest feed rate a configuration allows.
pub const MAX_RATE_PER_MS: u64 = 20;

/// Where a message came from: iceoryx2's unique publisher port id.
pub type Origin = u128;

#[derive(Debug, Clone, Copy, PartialEq)]
struct Port {
    origin: Origin,
    session: u64,
    sequence: u64,
    accepted_at: Instant,
    /// Since when every message of this port was refused as out of order.
    refused_since: Option<Instant>,
}

/// How a message that may be taken fits its port's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Placement {
    /// The first message seen from this port.
    NewPort,
    /// A new session of a known port.
    NewSession,
    /// The next message of the port's session.
    Next,
    /// Taken after the port's messages were refused for `resync_after`.
    Resync,
}

/// The order of one service's messages, per publisher port.
#[derive(Debug, Clone)]
pub struct Sequencer {
    ports: [Option<Port>; PORTS],
    resync_after: Duration,
}

impl Sequencer {
    pub fn new(resync_after: Duration) -> Self {
        Self {
            ports: [None; PORTS],
            resync_after,
        }
    }

    /// Where a message from `origin` would go, or why it is refused (the
    /// refusal is noted for rule 4). Nothing is recorded until
    /// [`Sequencer::record`]: a message refused for another reason must
    /// not move the order.
    pub fn place(
        &mut self,
        origin: Origin,
        session: u64,
        sequence: u64,
        now: Instant,
    ) -> Result<Placement, Rejected> {
        let resync_after = self.resync_after;
        let Some(port) = self.port_mut(origin) else {
            return Ok(Placement::NewPort);
        };
        if port.session != session {
            return Ok(Placement::NewSession);
        }
        let refused = if sequence <= port.sequence {
            Rejected {
                reason: RejectReason::SequenceBackwards,
                detail: format!(
                    "sequence {sequence} after {} in the same session",
                    port.sequence
                ),
            }
        } else {
            let elapsed = now.saturating_duration_since(port.accepted_at);
            let allowed = MAX_JUMP.saturating_add(
                MAX_RATE_PER_MS
                    .saturating_mul(u64::try_from(elapsed.as_millis()).unwrap_or(u64::MAX)),
            );
            let jump = sequence - port.sequence;
            if jump <= allowed {
                return Ok(Placement::Next);
            }
            Rejected {
                reason: RejectReason::SequenceJump,
                detail: format!(
                    "sequence {sequence} jumps {jump} ahead of {} in {} ms, more than the {allowed} its publisher could have sent",
                    port.sequence,
                    elapsed.as_millis()
                ),
            }
        };
        let since = *port.refused_since.get_or_insert(now);
        if now.saturating_duration_since(since) >= resync_after {
            return Ok(Placement::Resync);
        }
        Err(refused)
    }

    /// Records an accepted message as its port's latest.
    pub fn record(&mut self, origin: Origin, session: u64, sequence: u64, now: Instant) {
        let entry = Port {
            origin,
            session,
            sequence,
            accepted_at: now,
            refused_since: None,
        };
        if let Some(port) = self.port_mut(origin) {
            *port = entry;
            return;
        }
        // A free slot, else the port heard from least recently: forgetting
        // a port only ever lets its next message in.
        let slot = self
            .ports
            .iter()
            .position(Option::is_none)
            .or_else(|| (0..PORTS).min_by_key(|&k| self.ports[k].map(|p| p.accepted_at)))
            .unwrap_or(0);
        self.ports[slot] = Some(entry);
    }

    fn port_mut(&mut self, origin: Origin) -> Option<&mut Port> {
        self.ports.iter_mut().flatten().find(|p| p.origin == origin)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FEED: Origin = 1;
    const ATTACKER: Origin = 2;

    fn take(s: &mut Sequencer, origin: Origin, session: u64, seq: u64, now: Instant) -> Placement {
        let placed = s.place(origin, session, seq, now).unwrap();
        s.record(origin, session, seq, now);
        placed
    }

    #[test]
    fn another_port_in_the_feeds_session_cannot_move_its_sequence() {
        let t = Instant::now();
        let mut s = Sequencer::new(Duration::from_millis(500));
        assert_eq!(take(&mut s, FEED, 7, 1, t), Placement::NewPort);
        assert_eq!(take(&mut s, ATTACKER, 7, u64::MAX, t), Placement::NewPort);
        assert_eq!(take(&mut s, FEED, 7, 2, t), Placement::Next);
    }

    #[test]
    fn within_a_port_the_sequence_grows_by_what_it_could_have_sent() {
        let t = Instant::now();
        let mut s = Sequencer::new(Duration::from_millis(500));
        take(&mut s, FEED, 7, 10, t);
        let back = s.place(FEED, 7, 10, t).unwrap_err();
        assert_eq!(back.reason, RejectReason::SequenceBackwards);
        assert!(
            back.detail
                .contains("sequence 10 after 10 in the same session")
        );
        let far = s.place(FEED, 7, u64::MAX, t).unwrap_err();
        assert_eq!(far.reason, RejectReason::SequenceJump);
        assert_eq!(s.place(FEED, 7, 10 + MAX_JUMP, t), Ok(Placement::Next));
        let later = t + Duration::from_secs(60);
        let skipped = 10 + MAX_JUMP + 60_000 * MAX_RATE_PER_MS;
        assert_eq!(s.place(FEED, 7, skipped, later), Ok(Placement::Next));
        assert_eq!(take(&mut s, FEED, 8, 1, later), Placement::NewSession);
    }

    #[test]
    fn a_port_refused_for_resync_after_is_taken_again() {
        let t = Instant::now();
        let resync = Duration::from_millis(500);
        let mut s = Sequencer::new(resync);
        take(&mut s, FEED, 7, 900, t);
        take(&mut s, FEED, 7, 1800, t);
        // The feed itself goes back (say a bridge forwarded a jump).
        assert!(s.place(FEED, 7, 5, t).is_err());
        assert!(s.place(FEED, 7, 6, t + resync / 2).is_err());
        assert_eq!(s.place(FEED, 7, 7, t + resync), Ok(Placement::Resync));
        s.record(FEED, 7, 7, t + resync);
        assert_eq!(s.place(FEED, 7, 8, t + resync), Ok(Placement::Next));
    }

    #[test]
    fn many_ports_evict_the_quietest_and_a_forgotten_port_is_let_in() {
        let t = Instant::now();
        let mut s = Sequencer::new(Duration::from_millis(500));
        take(&mut s, FEED, 7, 50, t);
        for k in 0..PORTS as u128 {
            take(&mut s, 100 + k, 1, 1, t + Duration::from_millis(1));
        }
        assert_eq!(s.place(FEED, 7, 3, t), Ok(Placement::NewPort));
    }
}
