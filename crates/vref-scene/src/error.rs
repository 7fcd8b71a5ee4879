use std::fmt;

/// Which camera a graph comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    /// The robot's RGB-D camera (columns of the correspondence matrix).
    Robot,
    /// The person's AR headset (rows of the correspondence matrix).
    Human,
}

impl fmt::Display for Side {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Side::Robot => "robot",
            Side::Human => "human",
        })
    }
}

/// A defect of one graph.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GraphError {
    #[error("graph has no objects, but one is required")]
    Empty,
    #[error("graph has {count} objects, more than the capacity of {capacity}")]
    TooManyObjects { count: usize, capacity: usize },
    #[error("object id {id} appears more than once")]
    DuplicateId { id: u64 },
    #[error("object id {id}: position[{axis}] is {value}, not a finite number")]
    NonFinitePosition { id: u64, axis: usize, value: f64 },
    #[error("object id {id}: position[{axis}] is {value}, beyond the limit of +-{limit}")]
    AbsurdPosition {
        id: u64,
        axis: usize,
        value: f64,
        limit: f64,
    },
    #[error("object id {id}: position_sigma[{axis}] is {value}, not a finite non-negative number")]
    BadPositionSigma { id: u64, axis: usize, value: f64 },
    #[error("object id {id}: feature[{index}] is {value}, not a finite number")]
    NonFiniteFeature { id: u64, index: usize, value: f32 },
    #[error(
        "object id {id}: feature has dimension {found}, the graph's first object has {expected}"
    )]
    FeatureDimMismatch {
        id: u64,
        expected: usize,
        found: usize,
    },
    #[error("edge [{a}, {b}] names object id {unknown}, which is not in the graph")]
    UnknownEdgeEndpoint { a: u64, b: u64, unknown: u64 },
    #[error("edge [{id}, {id}] joins an object to itself")]
    SelfLoop { id: u64 },
    #[error("object id {id} raised by {offset} is beyond the largest id")]
    IdOverflow { id: u64, offset: u64 },
    #[error("up is {up:?}, not a finite non-zero direction")]
    BadUp { up: [f64; 3] },
}

/// A defect of a pair of graphs and its ground truth.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PairError {
    #[error("{side} graph")]
    Graph {
        side: Side,
        #[source]
        source: GraphError,
    },
    #[error("features have dimension {human} in the human graph and {robot} in the robot graph")]
    FeatureDimsDiffer { human: usize, robot: usize },
    #[error("ground_truth[{index}] names {side} object id {id}, which is not in the {side} graph")]
    UnknownGroundTruthId { index: usize, side: Side, id: u64 },
    #[error("ground_truth[{index}] pairs {side} object id {id} a second time")]
    GroundTruthNotOneToOne { index: usize, side: Side, id: u64 },
}
