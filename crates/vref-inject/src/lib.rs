//! Messages a faulty or hostile publisher would write into vref's shared
//! memory, one kind of defect each, for `vref inject` and the fault tests.
//! Building is pure: publishing is the caller's business, so the same
//! messages can be checked here without any service.

mod kind;
mod scene;

pub use kind::{Kind, UnknownKind};
pub use scene::{VALID_FEATURE_DIM, robot_id, valid_objects};

use vref_scene::Side;
use vref_wire::{
    FRAME_NAME_LEN, MAX_FEATURE_DIM, ObjectEntry, PointingRay, SCHEMA_VERSION, SideCode,
    SnapshotHeader,
};

/// One message to publish.
#[derive(Debug, Clone, PartialEq)]
pub enum Message {
    /// A snapshot on its side's service; the header is written exactly as
    /// given, whatever the entries say.
    Snapshot {
        header: SnapshotHeader,
        entries: Vec<ObjectEntry>,
    },
    /// A pointing ray on the gesture service.
    Ray(PointingRay),
}

/// What a run of `Kind` needs to know about its surroundings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// The snapshot service written to (rays ignore it).
    pub side: Side,
    /// Session of every message of the run.
    pub session: u64,
    /// The receiver's `[scene] capacity`, which `count-over-capacity`
    /// exceeds by one.
    pub capacity: usize,
    pub timestamp_ns: u64,
}

/// A schema version no build speaks.
pub const UNKNOWN_SCHEMA_VERSION: u32 = SCHEMA_VERSION + 1000;
/// Far beyond any `max_abs_coordinate` a configuration may sensibly set.
pub const HUGE: f32 = 1.0e30;
/// Feature dimension of `feature-dim-other-side`: a valid snapshot whose
/// features differ in length from what `valid` (and the other side) sends.
pub const OTHER_FEATURE_DIM: usize = VALID_FEATURE_DIM - 2;
/// Sequences of `sequence-backwards` in round 0: the first is accepted,
/// the second goes back in the same session.
pub const BACKWARDS: [u64; 2] = [10, 5];

/// The messages of round `round` (0, 1, ...) of `kind`, in publishing
/// order. Sequences grow from round to round, so repeated rounds (`--count`)
/// are each judged on their own defect, not as going backwards.
pub fn messages(kind: Kind, target: &Target, round: u64) -> Vec<Message> {
    let sequence = round + 1;
    let snapshot = |objects: Vec<ObjectEntry>| snapshot_of(target, sequence, objects);
    let valid = || valid_objects(target.side);
    match kind {
        Kind::Valid => vec![snapshot(valid())],
        Kind::Nan => vec![snapshot(with_position(valid(), f32::NAN))],
        Kind::Inf => vec![snapshot(with_position(valid(), f32::INFINITY))],
        Kind::Huge => vec![snapshot(with_position(valid(), HUGE))],
        Kind::CountOverSlice => {
            let mut message = snapshot(valid());
            if let Message::Snapshot { header, entries } = &mut message {
                header.object_count = count_u32(entries.len() + 5);
            }
            vec![message]
        }
        Kind::CountOverCapacity => vec![snapshot(many_objects(target.side, target.capacity + 1))],
        Kind::FeatureDimTooLarge => {
            let mut message = snapshot(valid());
            if let Message::Snapshot { header, .. } = &mut message {
                header.feature_dim = count_u32(MAX_FEATURE_DIM + 1);
            }
            vec![message]
        }
        Kind::FeatureDimOtherSide => {
            let mut message = snapshot(valid());
            if let Message::Snapshot { header, .. } = &mut message {
                header.feature_dim = count_u32(OTHER_FEATURE_DIM);
            }
            vec![message]
        }
        Kind::DuplicateIds => {
            let mut objects = valid();
            if let [first, second, ..] = objects.as_mut_slice() {
                second.track_id = first.track_id;
            }
            vec![snapshot(objects)]
        }
        Kind::ZeroRay => vec![Message::Ray(zero_ray(target, sequence))],
        Kind::BadUp => {
            let mut message = snapshot(valid());
            if let Message::Snapshot { header, .. } = &mut message {
                header.set_up(Some([0.0; 3]));
            }
            vec![message]
        }
        Kind::SchemaVersion => {
            let mut message = snapshot(valid());
            if let Message::Snapshot { header, .. } = &mut message {
                header.schema_version = UNKNOWN_SCHEMA_VERSION;
            }
            vec![message]
        }
        Kind::SequenceBackwards => BACKWARDS
            .iter()
            .map(|s| snapshot_of(target, s + round * BACKWARDS[0], valid()))
            .collect(),
        Kind::FutureStamp | Kind::OldStamp => {
            let mut message = snapshot(valid());
            if let Message::Snapshot { header, .. } = &mut message {
                header.timestamp_ns = if kind == Kind::FutureStamp {
                    target.timestamp_ns.saturating_add(AN_HOUR_NS)
                } else {
                    target.timestamp_ns.saturating_sub(AN_HOUR_NS)
                };
            }
            vec![message]
        }
        Kind::HijackSequence => vec![snapshot_of(target, u64::MAX, valid())],
        Kind::HijackRay => vec![Message::Ray(hijack_ray(target))],
    }
}

/// How far `future-stamp` and `old-stamp` are off.
pub const AN_HOUR_NS: u64 = 3_600_000_000_000;

/// The human object `hijack-ray` points at.
pub const HIJACK_RAY_TARGET: u64 = 3;

fn hijack_ray(target: &Target) -> PointingRay {
    let at = valid_objects(Side::Human)
        .into_iter()
        .find(|o| o.track_id == HIJACK_RAY_TARGET)
        .map_or([0.0, 0.0, 1.0], |o| o.position);
    PointingRay {
        session: target.session,
        sequence: u64::MAX,
        timestamp_ns: target.timestamp_ns,
        origin: [0.0; 3],
        direction: at,
        cone_half_angle: 0.05,
        confidence: 0.9,
        schema_version: SCHEMA_VERSION,
        reserved: 0,
    }
}

fn snapshot_of(target: &Target, sequence: u64, entries: Vec<ObjectEntry>) -> Message {
    let (code, frame) = match target.side {
        Side::Robot => (SideCode::Robot, "robot_camera"),
        Side::Human => (SideCode::Human, "human_camera"),
    };
    let mut frame_name = [0u8; FRAME_NAME_LEN];
    frame_name[..frame.len()].copy_from_slice(frame.as_bytes());
    Message::Snapshot {
        header: SnapshotHeader {
            session: target.session,
            sequence,
            timestamp_ns: target.timestamp_ns,
            schema_version: SCHEMA_VERSION,
            side: code as u32,
            object_count: count_u32(entries.len()),
            feature_dim: count_u32(VALID_FEATURE_DIM),
            frame_name,
            up: [0.0; 3],
            flags: 0,
        },
        entries,
    }
}

/// Sets the first coordinate of the first object.
fn with_position(mut objects: Vec<ObjectEntry>, value: f32) -> Vec<ObjectEntry> {
    if let Some(first) = objects.first_mut() {
        first.position[0] = value;
    }
    objects
}

/// `count` well-formed objects with distinct ids, on a grid.
fn many_objects(side: Side, count: usize) -> Vec<ObjectEntry> {
    let template = valid_objects(side);
    (0..count)
        .map(|i| {
            let mut entry = template[i % template.len()];
            entry.track_id = 10_000 + i as u64;
            entry.position[0] += 0.01 * (i / template.len()) as f32;
            entry
        })
        .collect()
}

fn zero_ray(target: &Target, sequence: u64) -> PointingRay {
    PointingRay {
        session: target.session,
        sequence,
        timestamp_ns: target.timestamp_ns,
        origin: [0.0; 3],
        direction: [0.0; 3],
        cone_half_angle: 0.1,
        confidence: 0.9,
        schema_version: SCHEMA_VERSION,
        reserved: 0,
    }
}

fn count_u32(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

#[cfg(test)]
mod tests;
