use vref_wire::ObjectEntry;

/// Something a feed publishes, and when.
#[derive(Debug, Clone, PartialEq)]
pub struct Due<'a> {
    /// When to publish, nanoseconds since the Unix epoch; also the
    /// snapshot's capture time.
    pub at_ns: u64,
    pub publication: Publication<'a>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Publication<'a> {
    Snapshot {
        feature_dim: usize,
        entries: &'a [ObjectEntry],
        /// The view's up vector, as the wire carries it, where the source
        /// knows it.
        up: Option<[f32; 3]>,
    },
    Gesture {
        ray: Ray,
        /// What the person means, when the source knows (synthetic).
        target: Option<Target>,
    },
}

/// A pointing ray in the headset camera's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: [f32; 3],
    pub direction: [f32; 3],
    /// Radians.
    pub cone_half_angle: f32,
    pub confidence: f32,
}

/// The object a synthetic gesture points at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Target {
    /// The gesture slot: one target per slot.
    pub slot: i64,
    pub human_id: u64,
    pub robot_id: u64,
}
