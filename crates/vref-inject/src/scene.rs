use vref_scene::Side;
use vref_wire::{MAX_FEATURE_DIM, ObjectEntry};

/// Feature entries used by the valid scene: one colour channel per object.
pub const VALID_FEATURE_DIM: usize = 6;

/// Six objects on a table in the human camera's frame (metres).
const HUMAN: [(u64, [f32; 3]); VALID_FEATURE_DIM] = [
    (1, [-0.20, 0.10, 0.80]),
    (2, [0.00, 0.12, 0.95]),
    (3, [0.18, 0.08, 0.70]),
    (4, [0.25, 0.15, 1.05]),
    (5, [-0.10, 0.14, 1.15]),
    (6, [0.05, 0.05, 0.60]),
];

/// The robot's track id of human object `h`: unrelated numbering, as
/// between two real trackers.
pub fn robot_id(h: u64) -> u64 {
    1000 - 7 * h
}

/// The same table seen by the robot: rotated 90 degrees about the
/// vertical axis and shifted, so that a match needs the geometry, not the
/// coordinates.
fn robot_position([x, y, z]: [f32; 3]) -> [f32; 3] {
    [z - 0.9, y + 0.02, -x + 1.0]
}

/// A well-formed view of the table from `side`, which the other side's
/// view matches one to one (human object `h` is robot track
/// [`robot_id`]`(h)`).
pub fn valid_objects(side: Side) -> Vec<ObjectEntry> {
    HUMAN
        .iter()
        .map(|&(h, position)| {
            let mut feature = [0.0; MAX_FEATURE_DIM];
            for (k, f) in feature.iter_mut().take(VALID_FEATURE_DIM).enumerate() {
                *f = if k as u64 == h - 1 { 1.0 } else { 0.05 };
            }
            let (track_id, position) = match side {
                Side::Human => (h, position),
                Side::Robot => (robot_id(h), robot_position(position)),
            };
            ObjectEntry {
                track_id,
                position,
                position_sigma: [0.01; 3],
                feature,
            }
        })
        .collect()
}
