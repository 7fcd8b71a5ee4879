// The derive expands to `unsafe impl ZeroCopySend`; the promise it makes
// (self-contained, `#[repr(C)]`, no pointers) holds for every type here.
#![allow(unsafe_code)]

use iceoryx2::prelude::ZeroCopySend;

/// Bumped on any change of layout or meaning of these types.
pub const SCHEMA_VERSION: u32 = 3;
/// Features travel inline, so each object entry has a fixed size.
pub const MAX_FEATURE_DIM: usize = 64;
/// Bytes of a snapshot's frame name (UTF-8, zero-padded).
pub const FRAME_NAME_LEN: usize = 32;
/// Next-best answers carried with a reference answer.
pub const MAX_ALTERNATIVES: usize = 3;

/// Which camera a snapshot comes from, as carried on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum SideCode {
    Robot = 0,
    Human = 1,
}

/// The user header of a snapshot; the objects follow as a slice.
#[derive(Debug, Clone, Copy, PartialEq, Default, ZeroCopySend)]
#[repr(C)]
#[type_name("vref::SnapshotHeader")]
pub struct SnapshotHeader {
    /// Random per publisher run: a restarted feed starts a new session,
    /// and its sequence numbers start again.
    pub session: u64,
    /// Increases by one per snapshot within a session.
    pub sequence: u64,
    /// Capture time, nanoseconds since the Unix epoch.
    pub timestamp_ns: u64,
    pub schema_version: u32,
    /// A [`SideCode`].
    pub side: u32,
    /// Objects used in the slice (the slice may be longer).
    pub object_count: u32,
    /// Entries of each object's `feature` that are used.
    pub feature_dim: u32,
    /// Camera frame the positions are in, e.g. "robot_camera".
    pub frame_name: [u8; FRAME_NAME_LEN],
    /// Which way is up (against gravity) in the camera frame; any
    /// non-zero length. Valid with [`SnapshotHeader::FLAG_UP`], else
    /// unknown (and ignored).
    pub up: [f32; 3],
    /// Bits: [`SnapshotHeader::FLAG_UP`]. Unknown bits are 0 and readers
    /// ignore them.
    pub flags: u32,
}

impl SnapshotHeader {
    /// `up` holds the view's up vector. A flag rather than a zero vector
    /// for "unknown", so that a zero written by mistake is refused
    /// instead of read as "no gravity".
    pub const FLAG_UP: u32 = 1;

    /// The up vector the header carries, as sent (not checked).
    pub fn up(&self) -> Option<[f32; 3]> {
        (self.flags & Self::FLAG_UP != 0).then_some(self.up)
    }

    /// Sets or clears the up vector.
    pub fn set_up(&mut self, up: Option<[f32; 3]>) {
        match up {
            Some(v) => {
                self.up = v;
                self.flags |= Self::FLAG_UP;
            }
            None => {
                self.up = [0.0; 3];
                self.flags &= !Self::FLAG_UP;
            }
        }
    }
}

/// One object of a snapshot.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("vref::ObjectEntry")]
pub struct ObjectEntry {
    pub track_id: u64,
    /// Metres, in the snapshot's camera frame (x right, y down, z forward).
    pub position: [f32; 3],
    /// One standard deviation per axis, metres.
    pub position_sigma: [f32; 3],
    /// The first `feature_dim` entries are the appearance feature.
    pub feature: [f32; MAX_FEATURE_DIM],
}

/// A pointing gesture in the human view's frame.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("vref::PointingRay")]
pub struct PointingRay {
    /// As in [`SnapshotHeader::session`].
    pub session: u64,
    pub sequence: u64,
    pub timestamp_ns: u64,
    pub origin: [f32; 3],
    /// Need not be unit length; must not be zero.
    pub direction: [f32; 3],
    /// Objects within this angle of the ray are candidates, radians.
    pub cone_half_angle: f32,
    /// The gesture recogniser's confidence, 0..1.
    pub confidence: f32,
    pub schema_version: u32,
    pub reserved: u32,
}

/// What a reference query asks about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum QueryKind {
    /// "Which robot object is human object `human_object_id`?"
    HumanObject = 0,
    /// "Which robot object does this ray point at?"
    Ray = 1,
    /// "Which robot object does the latest gesture point at?"
    LatestGesture = 2,
}

/// A controller's question to the matcher.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("vref::ReferenceQuery")]
pub struct ReferenceQuery {
    /// Echoed in the answer.
    pub request_id: u64,
    pub human_object_id: u64,
    pub ray_origin: [f32; 3],
    pub ray_direction: [f32; 3],
    pub cone_half_angle: f32,
    /// A [`QueryKind`].
    pub kind: u32,
    pub schema_version: u32,
    pub reserved: u32,
}

impl ReferenceQuery {
    /// "Which robot object is human object `id`?" (request id 0: the
    /// client numbers its requests).
    pub fn human_object(id: u64) -> Self {
        Self {
            request_id: 0,
            human_object_id: id,
            ray_origin: [0.0; 3],
            ray_direction: [0.0; 3],
            cone_half_angle: 0.0,
            kind: QueryKind::HumanObject as u32,
            schema_version: SCHEMA_VERSION,
            reserved: 0,
        }
    }

    /// "Which robot object does this ray (human view frame) point at?"
    pub fn ray(origin: [f32; 3], direction: [f32; 3], cone_half_angle: f32) -> Self {
        Self {
            ray_origin: origin,
            ray_direction: direction,
            cone_half_angle,
            kind: QueryKind::Ray as u32,
            ..Self::human_object(0)
        }
    }

    /// "Which robot object does the latest gesture point at?"
    pub fn latest_gesture() -> Self {
        Self {
            kind: QueryKind::LatestGesture as u32,
            ..Self::human_object(0)
        }
    }
}

/// How a query was answered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum AnswerStatus {
    Ok = 0,
    /// Below the confidence threshold: see the alternatives.
    Ambiguous = 1,
    /// The referred object has no partner in the robot view.
    NoMatch = 2,
    /// A feed has not delivered a valid snapshot yet.
    NotReady = 3,
    /// A feed went silent; the answer uses old snapshots (see the ages).
    Stale = 4,
    BadRequest = 5,
}

/// A next-best candidate.
#[derive(Debug, Clone, Copy, PartialEq, Default, ZeroCopySend)]
#[repr(C)]
#[type_name("vref::Alternative")]
pub struct Alternative {
    pub robot_track_id: u64,
    pub confidence: f32,
    pub reserved: u32,
}

/// The matcher's answer.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("vref::ReferenceAnswer")]
pub struct ReferenceAnswer {
    pub request_id: u64,
    /// The human-view object the query resolved to.
    pub human_object_id: u64,
    pub robot_track_id: u64,
    /// Sequence numbers of the snapshots the answering solution used.
    pub robot_sequence: u64,
    pub human_sequence: u64,
    /// Capture age of those snapshots when the answer was sent (now minus
    /// their `timestamp_ns`), microseconds.
    pub robot_age_us: u64,
    pub human_age_us: u64,
    /// Time since the answering solution was finished, microseconds.
    pub solve_age_us: u64,
    /// Capture age of the pointing ray the answer used (latest-gesture
    /// queries), microseconds; 0 when no stored ray was used.
    pub ray_age_us: u64,
    /// The robot object's position in the robot camera frame, metres.
    pub position: [f32; 3],
    /// The answered object in the human view's camera frame, metres, so a
    /// headset can highlight it; valid with [`ReferenceAnswer::FLAG_HUMAN_POSITION`].
    pub human_frame_position: [f32; 3],
    /// Probability that the answer is right.
    pub confidence: f32,
    /// An [`AnswerStatus`].
    pub status: u32,
    pub alternative_count: u32,
    pub schema_version: u32,
    pub alternatives: [Alternative; MAX_ALTERNATIVES],
    /// Bits about how the answer was made ([`ReferenceAnswer::FLAG_SOLVED`]
    /// and the others). Unknown bits are 0 and readers ignore them.
    pub flags: u32,
    /// With [`ReferenceAnswer::FLAG_REFUSAL`]: why a `stale` or `not_ready`
    /// answer has nothing fresher, as the matcher's reject reason (the
    /// index of `MatcherStats.rejected`) of the latest snapshot refused on
    /// a side that has no newer accepted one; 0 without the flag. (It was
    /// a reserved field of zeros: the layout is unchanged.)
    pub refusal: u32,
}

impl AnswerStatus {
    pub const ALL: [AnswerStatus; 6] = [
        AnswerStatus::Ok,
        AnswerStatus::Ambiguous,
        AnswerStatus::NoMatch,
        AnswerStatus::NotReady,
        AnswerStatus::Stale,
        AnswerStatus::BadRequest,
    ];

    /// The status carried as `code` on the wire, if it is one.
    pub fn from_code(code: u32) -> Option<Self> {
        Self::ALL.into_iter().find(|s| *s as u32 == code)
    }

    pub fn name(self) -> &'static str {
        match self {
            AnswerStatus::Ok => "ok",
            AnswerStatus::Ambiguous => "ambiguous",
            AnswerStatus::NoMatch => "no_match",
            AnswerStatus::NotReady => "not_ready",
            AnswerStatus::Stale => "stale",
            AnswerStatus::BadRequest => "bad_request",
        }
    }
}

impl ReferenceAnswer {
    /// A real solve made the answering solution; without it the solution
    /// was carried over from the previous solve because both snapshots
    /// held exactly its objects (or there was no solution at all, when the
    /// status says it could not match). Answers never wait for a solve.
    pub const FLAG_SOLVED: u32 = 1;
    /// `human_frame_position` holds the answered object in the human
    /// view's frame.
    pub const FLAG_HUMAN_POSITION: u32 = 1 << 1;
    /// ... mapped there from the robot object through the estimated motion
    /// between the views; without this bit it is the human object's own
    /// measured position.
    pub const FLAG_HUMAN_POSITION_FROM_MOTION: u32 = 1 << 2;
    /// `refusal` holds the reject reason behind a `stale` or `not_ready`
    /// answer.
    pub const FLAG_REFUSAL: u32 = 1 << 3;

    /// An answer to request `request_id` with `status` and nothing found:
    /// no object, no confidence, no alternatives, no flags.
    pub fn empty(request_id: u64, status: AnswerStatus) -> Self {
        Self {
            request_id,
            human_object_id: 0,
            robot_track_id: 0,
            robot_sequence: 0,
            human_sequence: 0,
            robot_age_us: 0,
            human_age_us: 0,
            solve_age_us: 0,
            ray_age_us: 0,
            position: [0.0; 3],
            human_frame_position: [0.0; 3],
            confidence: 0.0,
            status: status as u32,
            alternative_count: 0,
            schema_version: SCHEMA_VERSION,
            alternatives: [Alternative::default(); MAX_ALTERNATIVES],
            flags: 0,
            refusal: 0,
        }
    }

    /// Whether [`Self::FLAG_SOLVED`] is set.
    pub fn solved(&self) -> bool {
        self.flags & Self::FLAG_SOLVED != 0
    }

    /// The answer's status; an unknown code reads as `bad_request`.
    pub fn status(&self) -> AnswerStatus {
        AnswerStatus::from_code(self.status).unwrap_or(AnswerStatus::BadRequest)
    }

    /// The alternatives actually carried.
    pub fn alternatives(&self) -> &[Alternative] {
        let n = (self.alternative_count as usize).min(MAX_ALTERNATIVES);
        &self.alternatives[..n]
    }
}

/// Room for the matcher's reject reasons (vref-reference's `RejectReason`
/// as index); spare slots stay zero, so reasons can be added without a
/// layout change.
pub const MAX_REJECT_REASONS: usize = 32;
/// Room for the answer statuses ([`AnswerStatus`] code as index).
pub const MAX_ANSWER_STATUSES: usize = 8;

/// What the matcher has done since it started, published periodically so
/// that other processes (soak, monitors) can watch it. Counters only
/// grow while one matcher process lives; a restarted matcher starts
/// again from zero with a new `pid` and `started_ns`.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("vref::MatcherStats")]
pub struct MatcherStats {
    /// When the matcher started, nanoseconds since the Unix epoch.
    pub started_ns: u64,
    /// When these figures were taken, nanoseconds since the Unix epoch.
    pub taken_ns: u64,
    pub uptime_ms: u64,
    /// Snapshot samples taken from each side's service, by [`SideCode`],
    /// valid or not.
    pub snapshots_received: [u64; 2],
    /// Of those, the ones that passed every check.
    pub snapshots_accepted: [u64; 2],
    /// Messages rejected, by reason index.
    pub rejected: [u64; MAX_REJECT_REASONS],
    /// Queries answered, by [`AnswerStatus`] code.
    pub answers: [u64; MAX_ANSWER_STATUSES],
    /// Matching problems solved.
    pub solves: u64,
    /// Resident memory of the matcher process, kB; 0 if unknown.
    pub rss_kb: u64,
    pub pid: u32,
    pub schema_version: u32,
}

impl Default for MatcherStats {
    fn default() -> Self {
        Self {
            started_ns: 0,
            taken_ns: 0,
            uptime_ms: 0,
            snapshots_received: [0; 2],
            snapshots_accepted: [0; 2],
            rejected: [0; MAX_REJECT_REASONS],
            answers: [0; MAX_ANSWER_STATUSES],
            solves: 0,
            rss_kb: 0,
            pid: 0,
            schema_version: SCHEMA_VERSION,
        }
    }
}

impl MatcherStats {
    /// Queries answered with `status`.
    pub fn answered(&self, status: AnswerStatus) -> u64 {
        self.answers[status as usize]
    }

    /// Queries answered, whatever the status.
    pub fn answered_total(&self) -> u64 {
        self.answers.iter().sum()
    }

    pub fn rejected_total(&self) -> u64 {
        self.rejected.iter().sum()
    }
}

/// Most pairs a published decision carries (one per human object).
pub const MAX_DECISION_PAIRS: usize = 1024;

/// The user header of the matcher's decision: what the latest finished
/// solve concluded about the whole scene. One entry per human object
/// follows as a slice.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("vref::DecisionHeader")]
pub struct DecisionHeader {
    /// (session, sequence) and capture time of the snapshots solved.
    pub robot_session: u64,
    pub robot_sequence: u64,
    pub robot_timestamp_ns: u64,
    pub human_session: u64,
    pub human_sequence: u64,
    pub human_timestamp_ns: u64,
    /// When the solve finished, nanoseconds since the Unix epoch.
    pub solved_ns: u64,
    /// How long the solve took, microseconds.
    pub solve_us: u64,
    /// The matcher's solve counter at this decision (1 for the first).
    pub solve_index: u64,
    /// Human camera frame to robot camera frame, `q = R p + t`, `R`
    /// row-major; valid with [`DecisionHeader::FLAG_MOTION`].
    pub rotation: [f32; 9],
    pub translation: [f32; 3],
    /// Entries used in the slice.
    pub pair_count: u32,
    /// Bits: [`DecisionHeader::FLAG_MOTION`].
    pub flags: u32,
    /// The matching method, zero-padded UTF-8 (e.g. "rigid").
    pub method: [u8; 16],
    pub schema_version: u32,
    /// The median of the entries' residuals (see
    /// [`DecisionEntry::residual`]); valid with
    /// [`DecisionHeader::FLAG_RESIDUALS`]. Near 2.4 (the median of a
    /// chi-squared with three degrees of freedom) when the stated errors
    /// are honest and the motion right; far above, the motion leaves its
    /// pairs further apart than the sensors say they err.
    pub residual_median: f32,
}

impl DecisionHeader {
    /// The method estimated a rigid motion between the views.
    pub const FLAG_MOTION: u32 = 1;
    /// At least one entry carries a residual: `residual_median` is valid.
    pub const FLAG_RESIDUALS: u32 = 2;
}

impl Default for DecisionHeader {
    fn default() -> Self {
        Self {
            robot_session: 0,
            robot_sequence: 0,
            robot_timestamp_ns: 0,
            human_session: 0,
            human_sequence: 0,
            human_timestamp_ns: 0,
            solved_ns: 0,
            solve_us: 0,
            solve_index: 0,
            rotation: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            translation: [0.0; 3],
            pair_count: 0,
            flags: 0,
            method: [0; 16],
            schema_version: SCHEMA_VERSION,
            residual_median: 0.0,
        }
    }
}

/// One human object's outcome in a decision.
#[derive(Debug, Clone, Copy, PartialEq, Default, ZeroCopySend)]
#[repr(C)]
#[type_name("vref::DecisionEntry")]
pub struct DecisionEntry {
    pub human_track_id: u64,
    /// The partner; valid with [`DecisionEntry::FLAG_PARTNER`].
    pub robot_track_id: u64,
    /// Probability that this outcome (a partner, or none) is right.
    pub confidence: f32,
    /// An [`AnswerStatus`]: `ok` (matched), `ambiguous` (below the
    /// threshold, with or without a partner) or `no_match`.
    pub status: u32,
    /// Bits: [`DecisionEntry::FLAG_PARTNER`], [`DecisionEntry::FLAG_RESIDUAL`].
    pub flags: u32,
    /// The pair's squared residual under the decision's motion, in units
    /// of the position errors both objects state (a squared Mahalanobis
    /// length, three degrees of freedom); valid with
    /// [`DecisionEntry::FLAG_RESIDUAL`]: a partner, a motion, and errors
    /// stated on both sides. An `ok` answer's is at most the matcher's
    /// `fit_limit`.
    pub residual: f32,
}

impl DecisionEntry {
    /// The human object was given a robot partner.
    pub const FLAG_PARTNER: u32 = 1;
    /// `residual` is valid.
    pub const FLAG_RESIDUAL: u32 = 2;
}

#[cfg(test)]
mod tests {
    use std::mem::{align_of, size_of};

    use super::*;

    #[test]
    fn query_constructors_ask_what_they_say_in_the_current_schema() {
        let human = ReferenceQuery::human_object(7);
        assert_eq!(
            (human.kind, human.human_object_id),
            (QueryKind::HumanObject as u32, 7)
        );
        let ray = ReferenceQuery::ray([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], 0.1);
        assert_eq!(ray.kind, QueryKind::Ray as u32);
        assert_eq!(
            (ray.ray_origin, ray.ray_direction, ray.cone_half_angle),
            ([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], 0.1)
        );
        assert_eq!(
            ReferenceQuery::latest_gesture().kind,
            QueryKind::LatestGesture as u32
        );
        for q in [human, ray, ReferenceQuery::latest_gesture()] {
            assert_eq!(
                (q.request_id, q.schema_version, q.reserved),
                (0, SCHEMA_VERSION, 0)
            );
        }
    }

    /// Every wire type is laid out without implicit padding: its size is
    /// the sum of its fields' sizes, so another language's mirror of it
    /// (and a byte-wise copy) sees no uninitialised bytes.
    #[test]
    fn wire_types_have_no_implicit_padding() {
        let cases: [(&str, usize, usize); 9] = [
            (
                "SnapshotHeader",
                size_of::<SnapshotHeader>(),
                3 * 8 + 4 * 4 + FRAME_NAME_LEN + 3 * 4 + 4,
            ),
            (
                "ObjectEntry",
                size_of::<ObjectEntry>(),
                8 + 6 * 4 + MAX_FEATURE_DIM * 4,
            ),
            ("PointingRay", size_of::<PointingRay>(), 3 * 8 + 10 * 4),
            (
                "ReferenceQuery",
                size_of::<ReferenceQuery>(),
                2 * 8 + 10 * 4,
            ),
            ("Alternative", size_of::<Alternative>(), 8 + 2 * 4),
            (
                "ReferenceAnswer",
                size_of::<ReferenceAnswer>(),
                9 * 8 + 10 * 4 + MAX_ALTERNATIVES * 16 + 2 * 4,
            ),
            (
                "MatcherStats",
                size_of::<MatcherStats>(),
                (3 + 2 + 2 + MAX_REJECT_REASONS + MAX_ANSWER_STATUSES + 2) * 8 + 2 * 4,
            ),
            (
                "DecisionHeader",
                size_of::<DecisionHeader>(),
                9 * 8 + 12 * 4 + 2 * 4 + 16 + 2 * 4,
            ),
            ("DecisionEntry", size_of::<DecisionEntry>(), 2 * 8 + 4 * 4),
        ];
        for (name, size, fields) in cases {
            assert_eq!(size, fields, "{name}: {size} bytes, fields {fields}");
        }
        assert_eq!(align_of::<ReferenceAnswer>(), 8);
        assert_eq!(align_of::<DecisionHeader>(), 8);
    }
}
