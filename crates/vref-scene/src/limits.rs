/// What a valid graph may hold. The defaults fit a tabletop in metres and
/// the CMU House images in pixels alike.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Most objects one graph may carry (the matcher preallocates for this).
    pub capacity: usize,
    /// Largest absolute coordinate accepted; anything beyond is a sensor or
    /// encoding fault, not a position.
    pub max_abs_coordinate: f64,
    /// Whether a graph with no objects is an error.
    pub require_objects: bool,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            capacity: 256,
            max_abs_coordinate: 1.0e5,
            require_objects: true,
        }
    }
}
