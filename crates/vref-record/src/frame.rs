use serde::{Deserialize, Serialize};
use vref_scene::Side;
use vref_wire::{MAX_FEATURE_DIM, ObjectEntry, PointingRay, SnapshotHeader};

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
    /// The view's up vector as sent (not checked), `None` if the snapshot
    /// said it was unknown.
    pub up: Option<[f32; 3]>,
}

impl RecordedSnapshot {
    pub fn side(&self) -> Side {
        if self.robot { Side::Robot } else { Side::Human }
    }

    /// A snapshot as published on `side`'s service. Recordings keep what
    /// was sent, even a malformed snapshot, so that replays reproduce
    /// faults; only the slice bounds are respected.
    pub fn from_wire(side: Side, header: &SnapshotHeader, entries: &[ObjectEntry]) -> Self {
        let count = (header.object_count as usize).min(entries.len());
        let dim = (header.feature_dim as usize).min(MAX_FEATURE_DIM);
        let end = header
            .frame_name
            .iter()
            .position(|&b| b == 0)
            .unwrap_or(header.frame_name.len());
        RecordedSnapshot {
            robot: side == Side::Robot,
            sequence: header.sequence,
            timestamp_ns: header.timestamp_ns,
            frame_name: String::from_utf8_lossy(&header.frame_name[..end]).into_owned(),
            feature_dim: header.feature_dim,
            objects: entries[..count]
                .iter()
                .map(|e| RecordedObject {
                    track_id: e.track_id,
                    position: e.position,
                    position_sigma: e.position_sigma,
                    feature: e.feature[..dim].to_vec(),
                })
                .collect(),
            up: header.up(),
        }
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

impl RecordedRay {
    /// A ray as published, valid or not.
    pub fn from_wire(r: &PointingRay) -> Self {
        RecordedRay {
            sequence: r.sequence,
            timestamp_ns: r.timestamp_ns,
            origin: r.origin,
            direction: r.direction,
            cone_half_angle: r.cone_half_angle,
            confidence: r.confidence,
        }
    }
}

/// The frames of a `VREFREC1` file: written before snapshots carried an
/// up vector. bincode's encoding is not self-describing, so a field added
/// to [`RecordedSnapshot`] needs the old shape to read old files.
pub(crate) mod v1 {
    use serde::Deserialize;

    use super::{RecordedObject, RecordedRay, RecordedSnapshot};

    #[derive(Deserialize)]
    pub(crate) enum Frame {
        Snapshot(Snapshot),
        Gesture(RecordedRay),
    }

    #[derive(Deserialize)]
    pub(crate) struct Snapshot {
        robot: bool,
        sequence: u64,
        timestamp_ns: u64,
        frame_name: String,
        feature_dim: u32,
        objects: Vec<RecordedObject>,
    }

    impl From<Frame> for super::Frame {
        fn from(frame: Frame) -> Self {
            match frame {
                Frame::Snapshot(s) => super::Frame::Snapshot(RecordedSnapshot {
                    robot: s.robot,
                    sequence: s.sequence,
                    timestamp_ns: s.timestamp_ns,
                    frame_name: s.frame_name,
                    feature_dim: s.feature_dim,
                    objects: s.objects,
                    up: None,
                }),
                Frame::Gesture(r) => super::Frame::Gesture(r),
            }
        }
    }
}
