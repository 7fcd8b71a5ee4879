use vref_scene::{GraphError, Side};

/// A defect of a message read from shared memory.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WireError {
    #[error("schema version {found}, this build speaks {expected}")]
    SchemaVersion { found: u32, expected: u32 },
    #[error("side code {0} is neither robot (0) nor human (1)")]
    UnknownSide(u32),
    #[error("snapshot claims to come from the {found} side on the {expected} side's service")]
    WrongSide { expected: Side, found: Side },
    #[error("header says {count} objects, but the slice holds {slice}")]
    CountExceedsSlice { count: u32, slice: usize },
    #[error("feature dimension {dim} exceeds the wire maximum of {max}")]
    FeatureDimTooLarge { dim: u32, max: usize },
    #[error("frame name is not UTF-8")]
    FrameNameNotUtf8,
    #[error("object id {id}: position uncertainty {value} is not a finite non-negative number")]
    BadUncertainty { id: u64, value: f32 },
    #[error(transparent)]
    Graph(#[from] GraphError),
    #[error("ray {field} is not finite")]
    NonFiniteRay { field: &'static str },
    #[error("ray direction has zero length")]
    ZeroRayDirection,
    #[error("ray cone half-angle {0} rad is outside (0, pi/2]")]
    BadConeAngle(f32),
    #[error("ray confidence {0} is outside [0, 1]")]
    BadConfidence(f32),
}
