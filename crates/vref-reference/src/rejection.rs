use std::fmt;

use vref_scene::GraphError;
use vref_wire::WireError;

/// Why an incoming message was rejected: one counter each.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RejectReason {
    SchemaVersion,
    WrongSide,
    CountExceedsSlice,
    FeatureDimTooLarge,
    FrameName,
    Uncertainty,
    Empty,
    TooManyObjects,
    DuplicateId,
    NonFinitePosition,
    AbsurdPosition,
    NonFiniteFeature,
    FeatureDimMismatch,
    FeatureDimOtherSide,
    SequenceBackwards,
    BadRay,
    /// Stamped further in the future than the clock skew allowed.
    TimestampFuture,
    /// Stamped longer ago than any capture time the matcher believes.
    TimestampTooOld,
    /// A sequence number further ahead than its publisher could have
    /// counted since its last accepted message.
    SequenceJump,
    /// A query from a client over its rate, dropped unanswered.
    QueryOverRate,
    /// An up vector (flagged as known) that is no direction: zero or not
    /// finite.
    BadUp,
}

impl RejectReason {
    /// In counter order: new reasons go at the end, so that the index of
    /// every earlier one (its slot in `MatcherStats::rejected`) stays.
    pub const ALL: [RejectReason; 21] = [
        RejectReason::SchemaVersion,
        RejectReason::WrongSide,
        RejectReason::CountExceedsSlice,
        RejectReason::FeatureDimTooLarge,
        RejectReason::FrameName,
        RejectReason::Uncertainty,
        RejectReason::Empty,
        RejectReason::TooManyObjects,
        RejectReason::DuplicateId,
        RejectReason::NonFinitePosition,
        RejectReason::AbsurdPosition,
        RejectReason::NonFiniteFeature,
        RejectReason::FeatureDimMismatch,
        RejectReason::FeatureDimOtherSide,
        RejectReason::SequenceBackwards,
        RejectReason::BadRay,
        RejectReason::TimestampFuture,
        RejectReason::TimestampTooOld,
        RejectReason::SequenceJump,
        RejectReason::QueryOverRate,
        RejectReason::BadUp,
    ];

    pub fn name(self) -> &'static str {
        match self {
            RejectReason::SchemaVersion => "schema_version",
            RejectReason::WrongSide => "wrong_side",
            RejectReason::CountExceedsSlice => "count_exceeds_slice",
            RejectReason::FeatureDimTooLarge => "feature_dim_too_large",
            RejectReason::FrameName => "frame_name",
            RejectReason::Uncertainty => "uncertainty",
            RejectReason::Empty => "empty",
            RejectReason::TooManyObjects => "too_many_objects",
            RejectReason::DuplicateId => "duplicate_id",
            RejectReason::NonFinitePosition => "non_finite_position",
            RejectReason::AbsurdPosition => "absurd_position",
            RejectReason::NonFiniteFeature => "non_finite_feature",
            RejectReason::FeatureDimMismatch => "feature_dim_mismatch",
            RejectReason::FeatureDimOtherSide => "feature_dim_other_side",
            RejectReason::SequenceBackwards => "sequence_backwards",
            RejectReason::BadRay => "bad_ray",
            RejectReason::TimestampFuture => "timestamp_future",
            RejectReason::TimestampTooOld => "timestamp_too_old",
            RejectReason::SequenceJump => "sequence_jump",
            RejectReason::QueryOverRate => "query_over_rate",
            RejectReason::BadUp => "bad_up",
        }
    }

    /// The counter a wire defect is counted under.
    pub fn of(error: &WireError) -> Self {
        match error {
            WireError::SchemaVersion { .. } => RejectReason::SchemaVersion,
            WireError::UnknownSide(_) | WireError::WrongSide { .. } => RejectReason::WrongSide,
            WireError::CountExceedsSlice { .. } => RejectReason::CountExceedsSlice,
            WireError::FeatureDimTooLarge { .. } => RejectReason::FeatureDimTooLarge,
            WireError::FrameNameNotUtf8 => RejectReason::FrameName,
            WireError::BadUncertainty { .. } => RejectReason::Uncertainty,
            WireError::Graph(g) => match g {
                GraphError::Empty => RejectReason::Empty,
                GraphError::TooManyObjects { .. } => RejectReason::TooManyObjects,
                GraphError::DuplicateId { .. } => RejectReason::DuplicateId,
                GraphError::NonFinitePosition { .. } => RejectReason::NonFinitePosition,
                GraphError::AbsurdPosition { .. } => RejectReason::AbsurdPosition,
                // The wire checks uncertainties first (BadUncertainty).
                GraphError::BadPositionSigma { .. } => RejectReason::Uncertainty,
                GraphError::NonFiniteFeature { .. } => RejectReason::NonFiniteFeature,
                GraphError::FeatureDimMismatch { .. } => RejectReason::FeatureDimMismatch,
                GraphError::BadUp { .. } => RejectReason::BadUp,
                // Snapshots carry no edges, and the wire never raises ids.
                GraphError::UnknownEdgeEndpoint { .. }
                | GraphError::SelfLoop { .. }
                | GraphError::IdOverflow { .. } => RejectReason::DuplicateId,
            },
            WireError::NonFiniteRay { .. }
            | WireError::ZeroRayDirection
            | WireError::BadConeAngle(_)
            | WireError::BadConfidence(_) => RejectReason::BadRay,
        }
    }
}

impl fmt::Display for RejectReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Counters of rejected messages, by reason.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Rejections {
    counts: [u64; RejectReason::ALL.len()],
}

impl Rejections {
    pub fn count(&mut self, reason: RejectReason) {
        self.counts[reason as usize] += 1;
    }

    pub fn get(&self, reason: RejectReason) -> u64 {
        self.counts[reason as usize]
    }

    pub fn total(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// Reasons with a non-zero count.
    pub fn nonzero(&self) -> impl Iterator<Item = (RejectReason, u64)> + '_ {
        RejectReason::ALL
            .into_iter()
            .map(|r| (r, self.get(r)))
            .filter(|(_, n)| *n > 0)
    }
}
