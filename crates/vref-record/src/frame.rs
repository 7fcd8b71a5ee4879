use serde::{Deserialize, Serialize};
use vref_scene::Side;

/// One recorded publication.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Frame {
    Snapshot(RecordedSnapshot),
    Gesture(RecordedRay),
}

impl Frame {
    /// When it was published, nanoseconds since the Unix epoch.
    pub fn timestamp_ns(&self) -> u64 {
        match self {
            Frame::Snapshot(s) => s.timestamp_ns,
            Frame::Gesture(r) => r.timestamp_ns,
        }
    }
}

/// A snapshot of one view as it was published.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordedSnapshot {
    /// `true` for the robot view, `false` for the human view.
    pub robot: bool,
    pub sequence: u64,
    pub timestamp_ns: u64,
    pub frame_name: String,
    pub feature_dim: u32,
    pub objects: Vec<RecordedObject>,
}

impl RecordedSnapshot {
    pub fn side(&self) -> Side {
        if self.robot { Side::Robot } else { Side::Human }
    }
}

/// One object of a recorded snapshot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordedObject {
    pub track_id: u64,
    pub position: [f32; 3],
    pub position_sigma: [f32; 3],
    pub feature: Vec<f32>,
}

/// A recorded pointing ray.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordedRay {
    pub sequence: u64,
    pub timestamp_ns: u64,
    pub origin: [f32; 3],
    pub direction: [f32; 3],
    pub cone_half_angle: f32,
    pub confidence: f32,
}
