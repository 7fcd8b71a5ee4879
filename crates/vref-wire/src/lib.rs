//! What crosses shared memory between vref's processes: the message types
//! (`#[repr(C)]`, `ZeroCopySend`, an explicit type name each, no implicit
//! padding), and their validation into scene types. Nothing read from
//! shared memory is trusted: [`validate_snapshot`] and
//! [`PointingRay::validate`] turn raw messages into checked values or a
//! typed [`WireError`].
//!
//! [`bytes`] writes them as bytes for recordings and reads them back.
//!
//! [`ipc`] names and creates every service in one place and holds the
//! publishers and the client library that robot tasks link; [`layout`]
//! describes the types for other languages.

pub mod bytes;
mod error;
pub mod fuzz_input;
pub mod ipc;
pub mod layout;
mod messages;
mod snapshot;

pub use error::WireError;
pub use messages::{
    Alternative, AnswerStatus, DecisionEntry, DecisionHeader, FRAME_NAME_LEN, MAX_ALTERNATIVES,
    MAX_ANSWER_STATUSES, MAX_DECISION_PAIRS, MAX_FEATURE_DIM, MAX_REJECT_REASONS, MatcherStats,
    ObjectEntry, PointingRay, QueryKind, ReferenceAnswer, ReferenceQuery, SCHEMA_VERSION, SideCode,
    SnapshotHeader,
};
pub use snapshot::{Ray, ValidSnapshot, validate_snapshot, wire_up};
