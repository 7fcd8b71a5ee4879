//! The latest of everything the viewer has seen, copied out of shared
//! memory: what one scene is drawn from.

use vref_wire::ipc::Decision;
use vref_wire::{MatcherStats, ObjectEntry, PointingRay, ReferenceAnswer, SnapshotHeader};

/// One view's objects as drawn: track id and position, in the view's
/// camera frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct View {
    pub frame_name: String,
    pub sequence: u64,
    pub timestamp_ns: u64,
    pub objects: Vec<(u64, [f64; 3])>,
    /// The view's up vector as sent (not checked), if it said one.
    pub up: Option<[f32; 3]>,
}

impl View {
    /// The objects a snapshot carries, as far as the slice holds them;
    /// objects at non-finite positions are left out (nothing could draw
    /// them), everything else is shown as sent.
    pub fn from_wire(header: &SnapshotHeader, entries: &[ObjectEntry]) -> Self {
        let count = (header.object_count as usize).min(entries.len());
        let end = header
            .frame_name
            .iter()
            .position(|&b| b == 0)
            .unwrap_or(header.frame_name.len());
        Self {
            frame_name: String::from_utf8_lossy(&header.frame_name[..end]).into_owned(),
            sequence: header.sequence,
            timestamp_ns: header.timestamp_ns,
            objects: entries[..count]
                .iter()
                .filter(|e| e.position.iter().all(|v| v.is_finite()))
                .map(|e| (e.track_id, e.position.map(f64::from)))
                .collect(),
            up: header.up(),
        }
    }

    pub fn position(&self, id: u64) -> Option<[f64; 3]> {
        self.objects.iter().find(|(i, _)| *i == id).map(|(_, p)| *p)
    }
}

/// An answer the viewer asked for, and how long it took.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Asked {
    pub answer: ReferenceAnswer,
    pub round_trip_us: u64,
    /// When the answer arrived, nanoseconds since the Unix epoch.
    pub received_ns: u64,
}

/// The latest of each service.
#[derive(Debug, Clone, Default)]
pub struct Latest {
    pub robot: Option<View>,
    pub human: Option<View>,
    pub ray: Option<PointingRay>,
    pub decision: Option<Decision>,
    pub answer: Option<Asked>,
    pub stats: Option<MatcherStats>,
}
