//! What the bridge lets in from the network. A headset message passes
//! five checks, cheapest first, and is refused (counted by reason) at the
//! first it fails:
//!
//! 1. size: at most the configured bytes;
//! 2. encoding and decoding: one of the message's two declared encodings,
//!    well-formed;
//! 3. session: one headset at a time. Another session is refused while the
//!    current one is live, and takes over once it has been silent for the
//!    takeover time (a restarted headset);
//! 4. validation: vref-wire's, the matcher's own checks;
//! 5. order: the matcher's own sequence rules ([`vref_reference::Sequencer`]):
//!    within a session a sequence grows, by no more than the headset could
//!    have counted, and a session whose messages have all been refused as
//!    out of order for the takeover time is taken again from its next one.
//!    One message with a huge sequence number therefore never locks the
//!    headset out;
//! 6. rate: at most the configured rate per stream (a token bucket), spent
//!    only by the current session, so a flood from elsewhere never takes
//!    the headset's share.
//!
//! A message that passes is restamped as the bridge's own publication: the
//! bridge's session (new at every start, so the matcher sees a restarted
//! bridge as a new publisher), its own sequence, and the robot's clock at
//! arrival (headset clocks are not trusted to agree with the robot's).

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};
use vref_reference::{RejectReason, Rejected, Sequencer};
use vref_scene::{Limits, Side};
use vref_wire::{ObjectEntry, PointingRay, ReferenceQuery, SnapshotHeader, WireError};

use crate::format::{Format, Message};
use crate::rate::RateLimit;
use crate::{CodecError, binary, json};

/// Why a network message was not passed on.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Refusal {
    #[error("{bytes} bytes exceed the limit of {max}")]
    TooLarge { bytes: usize, max: usize },
    #[error(transparent)]
    Codec(#[from] CodecError),
    #[error(transparent)]
    Invalid(#[from] WireError),
    /// Out of order within the headset's session (backwards, or a jump
    /// further than it could have counted): the matcher's reasons.
    #[error("session {session}: {refused}")]
    Order { session: u64, refused: Rejected },
    #[error("session {session} while session {current} is live (one headset at a time)")]
    OtherSession { session: u64, current: u64 },
    #[error("over the rate limit")]
    RateLimited,
}

impl Refusal {
    /// The counter it goes to: the matcher's reason names for invalid
    /// messages, so both count a defect under one name.
    pub fn name(&self) -> &'static str {
        match self {
            Refusal::TooLarge { .. } => "too_large",
            Refusal::Codec(CodecError::Encoding { .. }) => "encoding",
            Refusal::Codec(_) => "malformed",
            Refusal::Invalid(e) => RejectReason::of(e).name(),
            Refusal::Order { refused, .. } => refused.reason.name(),
            Refusal::OtherSession { .. } => "other_session",
            Refusal::RateLimited => "rate_limited",
        }
    }
}

/// Messages of one stream: received, passed on, refused by reason.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct StreamCounters {
    pub received: u64,
    pub passed: u64,
    pub refused: BTreeMap<String, u64>,
}

impl StreamCounters {
    fn note<T>(&mut self, result: &Result<T, Refusal>) {
        self.received += 1;
        match result {
            Ok(_) => self.passed += 1,
            Err(refusal) => self.refuse(refusal.name()),
        }
    }

    pub fn refuse(&mut self, reason: &str) {
        *self.refused.entry(reason.to_owned()).or_default() += 1;
    }

    pub fn refused_total(&self) -> u64 {
        self.refused.values().sum()
    }
}

/// The headset session a stream currently follows.
#[derive(Debug, Clone, Copy)]
struct Current {
    session: u64,
    seen: Instant,
}

/// The network carries no publisher identity the way iceoryx2's port id
/// does: the session is the headset's, so all of a stream is one origin.
const HEADSET: vref_reference::Origin = 0;

/// One headset stream (snapshots or rays).
#[derive(Debug)]
struct Stream {
    rate: RateLimit,
    current: Option<Current>,
    order: Sequencer,
    /// The bridge's own sequence of what it passed on.
    sequence: u64,
    counters: StreamCounters,
}

impl Stream {
    fn new(rate_hz: f64, resync_after: Duration) -> Self {
        Self {
            rate: RateLimit::new(rate_hz),
            current: None,
            order: Sequencer::new(resync_after),
            sequence: 0,
            counters: StreamCounters::default(),
        }
    }

    /// Check 3.
    fn session(&self, session: u64, takeover: Duration, now: Instant) -> Result<(), Refusal> {
        match self.current {
            Some(current)
                if current.session != session
                    && now.saturating_duration_since(current.seen) < takeover =>
            {
                Err(Refusal::OtherSession {
                    session,
                    current: current.session,
                })
            }
            _ => Ok(()),
        }
    }

    /// Checks 5 and 6, after validation: only a message that would
    /// otherwise pass counts towards its session's resynchronisation, and
    /// only one in order spends the rate.
    fn admit(&mut self, session: u64, sequence: u64, now: Instant) -> Result<(), Refusal> {
        self.order
            .place(HEADSET, session, sequence, now)
            .map_err(|refused| Refusal::Order { session, refused })?;
        if !self.rate.admit(now) {
            return Err(Refusal::RateLimited);
        }
        Ok(())
    }

    /// The message is the session's latest, and gets the bridge's next
    /// sequence.
    fn commit(&mut self, session: u64, sequence: u64, now: Instant) -> u64 {
        self.current = Some(Current { session, seen: now });
        self.order.record(HEADSET, session, sequence, now);
        self.sequence += 1;
        self.sequence
    }
}

/// What the bridge's headset-in direction needs to know.
#[derive(Debug, Clone, PartialEq)]
pub struct IntakeLimits {
    pub scene: Limits,
    pub max_message_bytes: usize,
    pub max_snapshot_rate_hz: f64,
    pub max_gesture_rate_hz: f64,
    pub session_takeover: Duration,
}

/// The checks of headset snapshots and rays, and their counters.
#[derive(Debug)]
pub struct HeadsetIntake {
    limits: IntakeLimits,
    session: u64,
    snapshots: Stream,
    rays: Stream,
}

impl HeadsetIntake {
    /// `session` is the bridge's own, new at every start.
    pub fn new(limits: IntakeLimits, session: u64) -> Self {
        Self {
            snapshots: Stream::new(limits.max_snapshot_rate_hz, limits.session_takeover),
            rays: Stream::new(limits.max_gesture_rate_hz, limits.session_takeover),
            limits,
            session,
        }
    }

    /// A snapshot payload labelled `encoding`, arrived at `now` (`now_ns`
    /// on the robot's clock): the header and objects to publish, or why
    /// not.
    pub fn snapshot(
        &mut self,
        encoding: &str,
        payload: &[u8],
        now: Instant,
        now_ns: u64,
    ) -> Result<(SnapshotHeader, Vec<ObjectEntry>), Refusal> {
        let result = self.check_snapshot(encoding, payload, now, now_ns);
        self.snapshots.counters.note(&result);
        result
    }

    fn check_snapshot(
        &mut self,
        encoding: &str,
        payload: &[u8],
        now: Instant,
        now_ns: u64,
    ) -> Result<(SnapshotHeader, Vec<ObjectEntry>), Refusal> {
        within(payload, self.limits.max_message_bytes)?;
        let (mut header, entries) = match Message::Snapshot.format_of(encoding)? {
            Format::Json => json::decode_snapshot(payload)?,
            Format::Binary => binary::decode_snapshot(payload)?,
        };
        let (session, sequence) = (header.session, header.sequence);
        self.snapshots
            .session(session, self.limits.session_takeover, now)?;
        vref_wire::validate_snapshot(&header, &entries, Side::Human, &self.limits.scene)?;
        self.snapshots.admit(session, sequence, now)?;
        header.session = self.session;
        header.sequence = self.snapshots.commit(session, sequence, now);
        header.timestamp_ns = now_ns;
        Ok((header, entries))
    }

    /// A ray payload, as [`Self::snapshot`].
    pub fn ray(
        &mut self,
        encoding: &str,
        payload: &[u8],
        now: Instant,
        now_ns: u64,
    ) -> Result<PointingRay, Refusal> {
        let result = self.check_ray(encoding, payload, now, now_ns);
        self.rays.counters.note(&result);
        result
    }

    fn check_ray(
        &mut self,
        encoding: &str,
        payload: &[u8],
        now: Instant,
        now_ns: u64,
    ) -> Result<PointingRay, Refusal> {
        within(payload, self.limits.max_message_bytes)?;
        let mut ray = match Message::Ray.format_of(encoding)? {
            Format::Json => json::decode_ray(payload)?,
            Format::Binary => binary::decode_ray(payload)?,
        };
        let (session, sequence) = (ray.session, ray.sequence);
        self.rays
            .session(session, self.limits.session_takeover, now)?;
        ray.validate()?;
        self.rays.admit(session, sequence, now)?;
        ray.session = self.session;
        ray.sequence = self.rays.commit(session, sequence, now);
        ray.timestamp_ns = now_ns;
        Ok(ray)
    }

    pub fn snapshot_counters(&self) -> &StreamCounters {
        &self.snapshots.counters
    }

    pub fn ray_counters(&self) -> &StreamCounters {
        &self.rays.counters
    }

    /// For drops after the intake (the publishing side was busy).
    pub fn snapshot_counters_mut(&mut self) -> &mut StreamCounters {
        &mut self.snapshots.counters
    }

    pub fn ray_counters_mut(&mut self) -> &mut StreamCounters {
        &mut self.rays.counters
    }
}

/// The checks of remote queries: size, encoding, decoding, rate. What a
/// query asks is the matcher's to judge (it answers `bad_request`).
#[derive(Debug)]
pub struct QueryIntake {
    max_message_bytes: usize,
    rate: RateLimit,
    counters: StreamCounters,
}

impl QueryIntake {
    pub fn new(max_message_bytes: usize, max_query_rate_hz: f64) -> Self {
        Self {
            max_message_bytes,
            rate: RateLimit::new(max_query_rate_hz),
            counters: StreamCounters::default(),
        }
    }

    /// A query's payload and its encoding label (`None` without them):
    /// the query to ask and the encoding to answer in.
    pub fn query(
        &mut self,
        encoding: Option<&str>,
        payload: Option<&[u8]>,
        now: Instant,
    ) -> Result<(ReferenceQuery, Format), Refusal> {
        let result = self.check(encoding, payload, now);
        self.counters.note(&result);
        result
    }

    fn check(
        &mut self,
        encoding: Option<&str>,
        payload: Option<&[u8]>,
        now: Instant,
    ) -> Result<(ReferenceQuery, Format), Refusal> {
        let payload = payload.unwrap_or_default();
        within(payload, self.max_message_bytes)?;
        let format = Message::Query.format_of(encoding.unwrap_or_default())?;
        if !self.rate.admit(now) {
            return Err(Refusal::RateLimited);
        }
        let query = match format {
            Format::Json => json::decode_query(payload)?,
            Format::Binary => binary::decode_query(payload)?,
        };
        Ok((query, format))
    }

    pub fn counters(&self) -> &StreamCounters {
        &self.counters
    }

    pub fn counters_mut(&mut self) -> &mut StreamCounters {
        &mut self.counters
    }
}

fn within(payload: &[u8], max: usize) -> Result<(), Refusal> {
    if payload.len() > max {
        Err(Refusal::TooLarge {
            bytes: payload.len(),
            max,
        })
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use vref_wire::{FRAME_NAME_LEN, MAX_FEATURE_DIM, SCHEMA_VERSION, SideCode};

    use super::*;
    use crate::format;
    use crate::json::{ObjectJson, SnapshotIn};

    const BRIDGE_SESSION: u64 = 0xB1;

    fn intake() -> HeadsetIntake {
        HeadsetIntake::new(
            IntakeLimits {
                scene: Limits::default(),
                max_message_bytes: 64 * 1024,
                max_snapshot_rate_hz: 20.0,
                max_gesture_rate_hz: 20.0,
                session_takeover: Duration::from_millis(500),
            },
            BRIDGE_SESSION,
        )
    }

    fn objects() -> Vec<ObjectJson> {
        (1..=3)
            .map(|id| ObjectJson {
                track_id: id,
                position: [0.1 * id as f32, 0.0, 0.8],
                position_sigma: [0.01; 3],
                feature: vec![id as f32, 1.0],
            })
            .collect()
    }

    fn json_snapshot(session: u64, sequence: u64) -> Vec<u8> {
        json::encode_snapshot_in(&SnapshotIn {
            session,
            sequence,
            frame_name: Some("quest".to_owned()),
            up: None,
            objects: objects(),
        })
    }

    fn binary_snapshot(session: u64, sequence: u64, edit: impl Fn(&mut [ObjectEntry])) -> Vec<u8> {
        let mut frame_name = [0; FRAME_NAME_LEN];
        frame_name[..5].copy_from_slice(b"quest");
        let mut entries: Vec<ObjectEntry> = objects()
            .iter()
            .map(|o| {
                let mut feature = [0.0; MAX_FEATURE_DIM];
                feature[..2].copy_from_slice(&o.feature);
                ObjectEntry {
                    track_id: o.track_id,
                    position: o.position,
                    position_sigma: o.position_sigma,
                    feature,
                }
            })
            .collect();
        edit(&mut entries);
        let header = SnapshotHeader {
            session,
            sequence,
            timestamp_ns: 1,
            schema_version: SCHEMA_VERSION,
            side: SideCode::Human as u32,
            object_count: 3,
            feature_dim: 2,
            frame_name,
            up: [0.0; 3],
            flags: 0,
        };
        binary::encode_snapshot(&header, &entries)
    }

    fn binary() -> String {
        Message::Snapshot.encoding(Format::Binary)
    }

    #[test]
    fn good_snapshots_pass_restamped_as_the_bridges_own() {
        let mut intake = intake();
        let t0 = Instant::now();
        let (h, entries) = intake
            .snapshot(format::JSON, &json_snapshot(77, 5), t0, 1000)
            .unwrap();
        assert_eq!(
            (h.session, h.sequence, h.timestamp_ns),
            (BRIDGE_SESSION, 1, 1000)
        );
        assert_eq!(&h.frame_name[..6], b"quest\0");
        assert_eq!(entries.len(), 3);
        let step = Duration::from_millis(50);
        let (h, _) = intake
            .snapshot(&binary(), &binary_snapshot(77, 6, |_| {}), t0 + step, 2000)
            .unwrap();
        assert_eq!(
            (h.session, h.sequence, h.timestamp_ns),
            (BRIDGE_SESSION, 2, 2000)
        );
        let c = intake.snapshot_counters();
        assert_eq!((c.received, c.passed, c.refused_total()), (2, 2, 0));
    }

    #[test]
    fn each_defect_is_refused_under_its_own_name_and_changes_nothing() {
        let mut intake = intake();
        let t0 = Instant::now();
        let step = Duration::from_millis(60);
        intake
            .snapshot(format::JSON, &json_snapshot(1, 10), t0, 0)
            .unwrap();
        let nan = binary_snapshot(1, 11, |e| e[0].position[1] = f32::NAN);
        let dup = binary_snapshot(1, 12, |e| e[1].track_id = e[0].track_id);
        let cases: Vec<(String, Vec<u8>, &str)> = vec![
            (
                format::JSON.to_owned(),
                b"{\"session\": 1,".to_vec(),
                "malformed",
            ),
            (binary(), nan, "non_finite_position"),
            (binary(), dup, "duplicate_id"),
            (
                binary(),
                binary_snapshot(1, 13, |_| {})[..100].to_vec(),
                "malformed",
            ),
            ("zenoh/bytes".to_owned(), json_snapshot(1, 14), "encoding"),
            (
                format::JSON.to_owned(),
                vec![b' '; 64 * 1024 + 1],
                "too_large",
            ),
            (
                format::JSON.to_owned(),
                json_snapshot(1, 10),
                "sequence_backwards",
            ),
            (
                format::JSON.to_owned(),
                json_snapshot(2, 1),
                "other_session",
            ),
        ];
        for (i, (encoding, payload, reason)) in cases.iter().enumerate() {
            let at = t0 + step * (i as u32 + 1);
            let refusal = intake.snapshot(encoding, payload, at, 0).unwrap_err();
            assert_eq!(refusal.name(), *reason, "case {i}: {refusal}");
        }
        let c = intake.snapshot_counters().clone();
        assert_eq!(c.passed, 1);
        assert_eq!(c.refused.get("malformed"), Some(&2));
        assert_eq!(c.refused_total(), cases.len() as u64);
        // Nothing refused moved the session on: its next snapshot passes
        // with the bridge's next sequence.
        let at = t0 + step * 20;
        let (h, _) = intake
            .snapshot(format::JSON, &json_snapshot(1, 11), at, 0)
            .unwrap();
        assert_eq!(h.sequence, 2);
    }

    /// The up vector passes through both encodings into the header the
    /// bridge publishes, and is checked as strictly as from shared memory.
    #[test]
    fn an_up_vector_passes_as_sent_and_a_bad_one_is_refused_as_bad_up() {
        let mut intake = intake();
        let t0 = Instant::now();
        let step = Duration::from_millis(60);
        let json_up = |sequence, up: &str| {
            let text = String::from_utf8(json_snapshot(1, sequence)).unwrap();
            text.replacen("{", &format!("{{\"up\": {up}, "), 1)
                .into_bytes()
        };
        let binary_up = |sequence, up: [f32; 3]| {
            let bytes = binary_snapshot(1, sequence, |_| {});
            let (mut header, entries) = binary::decode_snapshot(&bytes).unwrap();
            header.set_up(Some(up));
            binary::encode_snapshot(&header, &entries)
        };
        let (h, _) = intake
            .snapshot(format::JSON, &json_up(1, "[0, -2, 0]"), t0, 0)
            .unwrap();
        assert_eq!(h.up(), Some([0.0, -2.0, 0.0]));
        let (h, _) = intake
            .snapshot(&binary(), &binary_up(2, [0.0, 0.6, 0.8]), t0 + step, 0)
            .unwrap();
        assert_eq!(h.up(), Some([0.0, 0.6, 0.8]));
        // Absent or null: unknown.
        for (k, payload) in [json_snapshot(1, 3), json_up(4, "null")].iter().enumerate() {
            let at = t0 + step * (k as u32 + 2);
            let (h, _) = intake.snapshot(format::JSON, payload, at, 0).unwrap();
            assert_eq!(h.up(), None);
        }

        let cases: Vec<(String, Vec<u8>, &str)> = vec![
            (format::JSON.to_owned(), json_up(5, "[0, 0, 0]"), "bad_up"),
            (
                format::JSON.to_owned(),
                json_up(6, "[0, 1e-9, 0]"),
                "bad_up",
            ),
            // serde_json refuses a number beyond f32.
            (
                format::JSON.to_owned(),
                json_up(11, "[1e39, 0, 0]"),
                "malformed",
            ),
            (binary(), binary_up(7, [f32::NAN, 1.0, 0.0]), "bad_up"),
            (binary(), binary_up(8, [0.0, 1e-9, 0.0]), "bad_up"),
            (format::JSON.to_owned(), json_up(9, "[0, 1]"), "malformed"),
            (format::JSON.to_owned(), json_up(10, "\"up\""), "malformed"),
        ];
        for (i, (encoding, payload, reason)) in cases.iter().enumerate() {
            let at = t0 + step * (i as u32 + 4);
            let refusal = intake.snapshot(encoding, payload, at, 0).unwrap_err();
            assert_eq!(refusal.name(), *reason, "case {i}: {refusal}");
        }
        let c = intake.snapshot_counters();
        assert_eq!((c.passed, c.refused.get("bad_up")), (4, Some(&4)));
    }

    #[test]
    fn another_headset_takes_over_only_after_the_current_one_is_silent() {
        let mut intake = intake();
        let t0 = Instant::now();
        intake
            .snapshot(format::JSON, &json_snapshot(1, 1), t0, 0)
            .unwrap();
        let soon = t0 + Duration::from_millis(400);
        assert!(matches!(
            intake.snapshot(format::JSON, &json_snapshot(2, 1), soon, 0),
            Err(Refusal::OtherSession {
                session: 2,
                current: 1
            })
        ));
        let later = t0 + Duration::from_millis(500);
        intake
            .snapshot(format::JSON, &json_snapshot(2, 1), later, 0)
            .unwrap();
        // Now the first is the other one.
        let after = later + Duration::from_millis(50);
        assert_eq!(
            intake
                .snapshot(format::JSON, &json_snapshot(1, 2), after, 0)
                .unwrap_err()
                .name(),
            "other_session"
        );
    }

    /// Issue 40, case 2: before the bridge followed the matcher's
    /// sequence rules, this one message was taken as the session's latest
    /// and every later real one refused as `sequence_backwards`.
    #[test]
    fn one_message_with_a_huge_sequence_does_not_lock_the_headset_out() {
        let mut intake = intake();
        let t0 = Instant::now();
        let step = Duration::from_millis(33);
        intake
            .snapshot(format::JSON, &json_snapshot(1, 1), t0, 0)
            .unwrap();
        let far = intake
            .snapshot(format::JSON, &json_snapshot(1, u64::MAX), t0 + step, 0)
            .unwrap_err();
        assert_eq!(far.name(), "sequence_jump", "{far}");
        for sequence in 2..10 {
            let at = t0 + step * sequence as u32;
            intake
                .snapshot(format::JSON, &json_snapshot(1, sequence), at, 0)
                .unwrap();
        }
        let ray = |sequence| {
            json::encode_ray(&PointingRay {
                session: 1,
                sequence,
                timestamp_ns: 0,
                origin: [0.0; 3],
                direction: [0.0, 0.0, 1.0],
                cone_half_angle: 0.1,
                confidence: 0.9,
                schema_version: SCHEMA_VERSION,
                reserved: 0,
            })
        };
        intake.ray(format::JSON, &ray(1), t0, 0).unwrap();
        let far = intake.ray(format::JSON, &ray(u64::MAX), t0, 0).unwrap_err();
        assert_eq!(far.name(), "sequence_jump");
        intake.ray(format::JSON, &ray(2), t0 + step, 0).unwrap();
    }

    /// A sender in the headset's session that got ahead of it (a flood
    /// within the jump limit) locks it out for the takeover time at most.
    #[test]
    fn a_session_refused_as_out_of_order_for_the_takeover_time_is_taken_again() {
        let mut intake = intake();
        let t0 = Instant::now();
        intake
            .snapshot(format::JSON, &json_snapshot(1, 1), t0, 0)
            .unwrap();
        let ahead = t0 + Duration::from_millis(10);
        intake
            .snapshot(format::JSON, &json_snapshot(1, 900), ahead, 0)
            .unwrap();
        let refused = |sequence: u64, ms: u64, intake: &mut HeadsetIntake| {
            let at = ahead + Duration::from_millis(ms);
            intake
                .snapshot(format::JSON, &json_snapshot(1, sequence), at, 0)
                .map(|(h, _)| h.sequence)
        };
        assert_eq!(
            refused(2, 100, &mut intake).unwrap_err().name(),
            "sequence_backwards"
        );
        assert!(refused(3, 400, &mut intake).is_err());
        // 500 ms (the takeover time) after the first refusal.
        assert_eq!(refused(4, 600, &mut intake), Ok(3));
        assert_eq!(refused(5, 650, &mut intake), Ok(4));
    }

    #[test]
    fn a_flood_is_cut_to_the_rate_and_a_foreign_flood_takes_none_of_it() {
        let mut intake = intake();
        let t0 = Instant::now();
        intake
            .snapshot(format::JSON, &json_snapshot(1, 1), t0, 0)
            .unwrap();
        // A foreign session floods: all refused, none of the rate spent.
        for i in 0..500 {
            let at = t0 + Duration::from_micros(i);
            let r = intake.snapshot(format::JSON, &json_snapshot(9, i + 1), at, 0);
            assert_eq!(r.unwrap_err().name(), "other_session");
        }
        // The headset itself floods within a millisecond: its burst passes
        // (20 Hz: 5, one of them spent above), the rest is cut.
        let passed = (2..502)
            .filter(|s| {
                let at = t0 + Duration::from_nanos(*s);
                intake
                    .snapshot(format::JSON, &json_snapshot(1, *s), at, 0)
                    .is_ok()
            })
            .count();
        assert_eq!(passed, 4);
        let c = intake.snapshot_counters();
        assert_eq!(c.refused.get("rate_limited"), Some(&496));
        assert_eq!(c.refused.get("other_session"), Some(&500));
    }

    #[test]
    fn rays_are_checked_the_same_way() {
        let mut intake = intake();
        let t0 = Instant::now();
        let ray = |session, sequence, direction: [f32; 3]| {
            json::encode_ray(&PointingRay {
                session,
                sequence,
                timestamp_ns: 0,
                origin: [0.0; 3],
                direction,
                cone_half_angle: 0.1,
                confidence: 0.9,
                schema_version: SCHEMA_VERSION,
                reserved: 0,
            })
        };
        let r = intake
            .ray(format::JSON, &ray(4, 1, [0.0, 0.0, 1.0]), t0, 55)
            .unwrap();
        assert_eq!(
            (r.session, r.sequence, r.timestamp_ns),
            (BRIDGE_SESSION, 1, 55)
        );
        let at = t0 + Duration::from_millis(100);
        let zero = intake
            .ray(format::JSON, &ray(4, 2, [0.0; 3]), at, 0)
            .unwrap_err();
        assert_eq!(zero.name(), "bad_ray");
        let bin = Message::Ray.encoding(Format::Binary);
        let short = intake.ray(&bin, &[0; 63], at, 0).unwrap_err();
        assert_eq!(short.name(), "malformed");
        assert_eq!(intake.ray_counters().passed, 1);
    }

    #[test]
    fn queries_need_a_declared_encoding_and_a_whole_payload() {
        let mut intake = QueryIntake::new(1024, 100.0);
        let t0 = Instant::now();
        let json = br#"{"kind": "human_object", "human_object_id": 3}"#;
        let (q, format) = intake.query(Some(format::JSON), Some(json), t0).unwrap();
        assert_eq!((q.human_object_id, format), (3, Format::Json));
        let bin = Message::Query.encoding(Format::Binary);
        let (_, format) = intake
            .query(Some(&bin), Some(&binary::encode_query(&q)), t0)
            .unwrap();
        assert_eq!(format, Format::Binary);
        for (encoding, payload, reason) in [
            (None, None, "encoding"),
            (Some(format::JSON), None, "malformed"),
            (Some(bin.as_str()), Some(&[0u8; 55][..]), "malformed"),
            (Some(format::JSON), Some(&[b'x'; 1025][..]), "too_large"),
        ] {
            let refusal = intake.query(encoding, payload, t0).unwrap_err();
            assert_eq!(refusal.name(), reason, "{refusal}");
        }
        assert_eq!(intake.counters().passed, 2);
    }
}
