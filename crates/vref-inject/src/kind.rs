use std::fmt;
use std::str::FromStr;

/// One kind of message `vref inject` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// A well-formed snapshot, for tests and demos.
    Valid,
    /// A NaN coordinate.
    Nan,
    /// An infinite coordinate.
    Inf,
    /// A finite but absurd coordinate (1e30).
    Huge,
    /// A header object count larger than the slice.
    CountOverSlice,
    /// More objects than the receiver's capacity, with a slice that large.
    CountOverCapacity,
    /// A header feature dimension beyond the wire's maximum.
    FeatureDimTooLarge,
    /// A valid snapshot whose feature dimension differs from the other
    /// side's.
    FeatureDimOtherSide,
    /// Two objects with one track id.
    DuplicateIds,
    /// A pointing ray with a zero direction.
    ZeroRay,
    /// A schema version nobody speaks.
    SchemaVersion,
    /// Sequence 10, then 5, in one session.
    SequenceBackwards,
    /// A valid snapshot stamped an hour in the future.
    FutureStamp,
    /// A valid snapshot stamped an hour ago.
    OldStamp,
    /// A valid snapshot in the live feed's session (read from the service,
    /// as any subscriber can) with the largest sequence number.
    HijackSequence,
    /// A valid ray in the live gesture feed's session with the largest
    /// sequence number, pointing at human object 3.
    HijackRay,
    /// An up vector flagged as known but zero.
    BadUp,
}

impl Kind {
    pub const ALL: [Kind; 17] = [
        Kind::Valid,
        Kind::Nan,
        Kind::Inf,
        Kind::Huge,
        Kind::CountOverSlice,
        Kind::CountOverCapacity,
        Kind::FeatureDimTooLarge,
        Kind::FeatureDimOtherSide,
        Kind::DuplicateIds,
        Kind::ZeroRay,
        Kind::SchemaVersion,
        Kind::SequenceBackwards,
        Kind::FutureStamp,
        Kind::OldStamp,
        Kind::HijackSequence,
        Kind::HijackRay,
        Kind::BadUp,
    ];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Valid => "valid",
            Kind::Nan => "nan",
            Kind::Inf => "inf",
            Kind::Huge => "huge",
            Kind::CountOverSlice => "count-over-slice",
            Kind::CountOverCapacity => "count-over-capacity",
            Kind::FeatureDimTooLarge => "feature-dim-too-large",
            Kind::FeatureDimOtherSide => "feature-dim-other-side",
            Kind::DuplicateIds => "duplicate-ids",
            Kind::ZeroRay => "zero-ray",
            Kind::SchemaVersion => "schema-version",
            Kind::SequenceBackwards => "sequence-backwards",
            Kind::FutureStamp => "future-stamp",
            Kind::OldStamp => "old-stamp",
            Kind::HijackSequence => "hijack-sequence",
            Kind::HijackRay => "hijack-ray",
            Kind::BadUp => "bad-up",
        }
    }

    /// Whether the receiver must have taken each message before the next
    /// is sent: a subscriber that wakes once for several snapshots judges
    /// only the newest, so `10, 5` sent back to back could read as `5`.
    pub fn needs_settling(self) -> bool {
        self == Kind::SequenceBackwards
    }

    /// Whether the messages go to the gesture service.
    pub fn is_ray(self) -> bool {
        matches!(self, Kind::ZeroRay | Kind::HijackRay)
    }

    /// Whether the run takes the session of the feed already publishing.
    pub fn hijacks(self) -> bool {
        matches!(self, Kind::HijackSequence | Kind::HijackRay)
    }

    /// All names, comma-separated, for error messages and help.
    pub fn names() -> String {
        Kind::ALL.map(Kind::name).join(", ")
    }
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A kind name that is not one of [`Kind::ALL`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown kind `{found}`; the kinds are: {}", Kind::names())]
pub struct UnknownKind {
    pub found: String,
}

impl FromStr for Kind {
    type Err = UnknownKind;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Kind::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| UnknownKind {
                found: s.to_owned(),
            })
    }
}
