/// Why a matching problem could not be built or solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MatchError {
    #[error("the {side} graph has no objects")]
    EmptyGraph { side: &'static str },
    #[error("features have dimension {human} in the human graph and {robot} in the robot graph")]
    FeatureDimsDiffer { human: usize, robot: usize },
    #[error("parameter `{name}` is {value}, but must be {expected}")]
    BadParameter {
        name: &'static str,
        value: f64,
        expected: &'static str,
    },
    #[error("score matrix entry ({row}, {col}) is {value}, not a finite number")]
    NonFiniteScore { row: usize, col: usize, value: f64 },
    #[error("score matrix has {len} entries, expected {rows} x {cols}")]
    ShapeMismatch {
        len: usize,
        rows: usize,
        cols: usize,
    },
    #[error("unknown method `{0}` (expected one of: appearance, sm, rrwm, paper, rigid, clipper)")]
    UnknownMethod(String),
    #[error("the matcher engine takes fully connected graphs; this one has an edge list")]
    EdgeListInEngine,
    #[error("unknown tier `{0}` (expected exact or live)")]
    UnknownTier(String),
    #[error("warm start has {len} entries, expected {expected}")]
    WarmStartShape { len: usize, expected: usize },
}
