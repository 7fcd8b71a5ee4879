//! The frames a scene is drawn in: a z-up world, the robot camera in it,
//! and the headset camera placed by the matcher's estimated motion, or
//! beside the robot's view when there is none.

use foxglove::messages::{FrameTransform, FrameTransforms, Quaternion, Timestamp};
use vref_wire::DecisionHeader;

use crate::geometry::{IDENTITY, f64s, quaternion_of, rotate, vector};
use crate::state::{Latest, View};

/// The root frame: x forward, y left, z up, as Foxglove's 3D panel
/// expects; the robot camera sits at its origin.
pub const WORLD_FRAME: &str = "world";
/// Camera frames when a snapshot names none (or both name the same).
pub const ROBOT_FRAME: &str = "robot_camera";
pub const HUMAN_FRAME: &str = "headset_camera";

/// Camera axes (x right, y down, z forward) in the world (x forward, y
/// left, z up), row-major.
const OPTICAL_IN_WORLD: [f64; 9] = [0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0];

/// The two camera frames' names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameNames {
    pub robot: String,
    pub human: String,
}

impl FrameNames {
    /// The snapshots' own names where they are usable.
    pub fn of(latest: &Latest) -> Self {
        let name = |view: &Option<View>, fallback: &str| {
            view.as_ref()
                .map(|v| v.frame_name.clone())
                .filter(|n| !n.is_empty() && n != WORLD_FRAME)
                .unwrap_or_else(|| fallback.to_owned())
        };
        let robot = name(&latest.robot, ROBOT_FRAME);
        let mut human = name(&latest.human, HUMAN_FRAME);
        if human == robot {
            human = format!("{human}_human");
        }
        Self { robot, human }
    }
}

/// Where the headset camera is drawn in the robot camera's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Placement {
    /// The matcher's estimate: a human-frame point `p` is at `R p + t`.
    Motion {
        rotation: Quaternion,
        translation: [f64; 3],
    },
    /// No estimate: the human view is drawn unrotated, shifted to stand
    /// beside the robot's (its positions are not comparable).
    Beside { offset: [f64; 3] },
}

impl Placement {
    /// The decision's motion if it carries a finite one, else beside.
    /// `gap` is the space left between the views drawn side by side.
    pub fn of(latest: &Latest, gap: f64) -> Self {
        if let Some(d) = &latest.decision
            && let Some(placement) = Self::from_motion(&d.header)
        {
            return placement;
        }
        Placement::Beside {
            offset: beside(latest.robot.as_ref(), latest.human.as_ref(), gap),
        }
    }

    fn from_motion(h: &DecisionHeader) -> Option<Self> {
        if h.flags & DecisionHeader::FLAG_MOTION == 0 {
            return None;
        }
        let finite = h
            .rotation
            .iter()
            .chain(&h.translation)
            .all(|v| v.is_finite());
        finite.then(|| Placement::Motion {
            rotation: quaternion_of(&h.rotation.map(f64::from)),
            translation: f64s(h.translation),
        })
    }

    pub fn has_motion(&self) -> bool {
        matches!(self, Placement::Motion { .. })
    }

    /// A human-frame point in the robot camera's frame, as drawn.
    pub fn to_robot(&self, p: [f64; 3]) -> [f64; 3] {
        let (q, t) = self.parts();
        let r = rotate(&q, p);
        [r[0] + t[0], r[1] + t[1], r[2] + t[2]]
    }

    fn parts(&self) -> (Quaternion, [f64; 3]) {
        match *self {
            Placement::Motion {
                rotation,
                translation,
            } => (rotation, translation),
            Placement::Beside { offset } => (IDENTITY, offset),
        }
    }
}

/// Shifts the human view to the right of the robot's (camera x) with
/// `gap` between them, at the robot view's mean height and depth.
fn beside(robot: Option<&View>, human: Option<&View>, gap: f64) -> [f64; 3] {
    let bounds = |v: Option<&View>| -> Option<([f64; 3], [f64; 3], [f64; 3])> {
        let objects = &v?.objects;
        if objects.is_empty() {
            return None;
        }
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let mut mean = [0.0; 3];
        for (_, p) in objects {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
                mean[k] += p[k] / objects.len() as f64;
            }
        }
        Some((lo, hi, mean))
    };
    match (bounds(robot), bounds(human)) {
        (Some((_, r_hi, r_mean)), Some((h_lo, _, h_mean))) => [
            r_hi[0] - h_lo[0] + gap,
            r_mean[1] - h_mean[1],
            r_mean[2] - h_mean[2],
        ],
        _ => [gap, 0.0, 0.0],
    }
}

/// World to robot camera, robot camera to headset camera.
pub fn transforms(names: &FrameNames, placement: &Placement, time: Timestamp) -> FrameTransforms {
    let (rotation, translation) = placement.parts();
    FrameTransforms {
        transforms: vec![
            FrameTransform {
                timestamp: Some(time),
                parent_frame_id: WORLD_FRAME.to_owned(),
                child_frame_id: names.robot.clone(),
                translation: Some(vector([0.0; 3])),
                rotation: Some(quaternion_of(&OPTICAL_IN_WORLD)),
            },
            FrameTransform {
                timestamp: Some(time),
                parent_frame_id: names.robot.clone(),
                child_frame_id: names.human.clone(),
                translation: Some(vector(translation)),
                rotation: Some(rotation),
            },
        ],
    }
}

#[cfg(test)]
mod tests {
    use vref_wire::ipc::Decision;

    use super::*;

    fn view(name: &str, points: &[[f64; 3]]) -> View {
        View {
            frame_name: name.to_owned(),
            objects: points
                .iter()
                .enumerate()
                .map(|(i, p)| (i as u64 + 1, *p))
                .collect(),
            ..View::default()
        }
    }

    #[test]
    fn the_robot_camera_looks_along_world_x_with_its_y_down() {
        let q = quaternion_of(&OPTICAL_IN_WORLD);
        let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
        assert!(close(rotate(&q, [0.0, 0.0, 1.0]), [1.0, 0.0, 0.0]));
        assert!(close(rotate(&q, [0.0, 1.0, 0.0]), [0.0, 0.0, -1.0]));
        assert!(close(rotate(&q, [1.0, 0.0, 0.0]), [0.0, -1.0, 0.0]));
    }

    #[test]
    fn a_decision_with_motion_places_the_headset_by_it() {
        let header = DecisionHeader {
            // A quarter turn about the camera's y axis, then 1 m forward.
            rotation: [0.0, 0.0, 1.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0],
            translation: [0.0, 0.0, 1.0],
            flags: DecisionHeader::FLAG_MOTION,
            ..DecisionHeader::default()
        };
        let latest = Latest {
            decision: Some(Decision {
                header,
                entries: Vec::new(),
            }),
            ..Latest::default()
        };
        let placement = Placement::of(&latest, 0.1);
        assert!(placement.has_motion());
        let p = placement.to_robot([1.0, 0.0, 0.0]);
        assert!((p[0]).abs() < 1e-6 && (p[2] - 0.0).abs() < 1e-6, "{p:?}");
        let p = placement.to_robot([0.0, 0.0, 1.0]);
        assert!(
            (p[0] - 1.0).abs() < 1e-6 && (p[2] - 1.0).abs() < 1e-6,
            "{p:?}"
        );

        let names = FrameNames::of(&latest);
        let tf = transforms(&names, &placement, Timestamp::new(1, 0));
        assert_eq!(tf.transforms.len(), 2);
        assert_eq!(tf.transforms[1].parent_frame_id, ROBOT_FRAME);
        assert_eq!(tf.transforms[1].child_frame_id, HUMAN_FRAME);
        assert_eq!(tf.transforms[1].translation, Some(vector([0.0, 0.0, 1.0])));
    }

    #[test]
    fn without_motion_the_human_view_stands_beside_the_robots() {
        let mut header = DecisionHeader::default();
        // A decision from a method without motion, and one with a broken one.
        for flags in [0, DecisionHeader::FLAG_MOTION] {
            header.flags = flags;
            header.translation = [f32::NAN, 0.0, 0.0];
            let latest = Latest {
                robot: Some(view("robot_camera", &[[-0.2, 0.0, 1.0], [0.2, 0.1, 1.2]])),
                human: Some(view("headset_camera", &[[-0.1, 0.0, 0.5], [0.1, 0.0, 0.7]])),
                decision: Some(Decision {
                    header,
                    entries: Vec::new(),
                }),
                ..Latest::default()
            };
            let placement = Placement::of(&latest, 0.3);
            assert!(!placement.has_motion());
            // The leftmost human object lands 0.3 m right of the rightmost
            // robot object, at the robot view's mean depth.
            let p = placement.to_robot([-0.1, 0.0, 0.6]);
            assert!((p[0] - 0.5).abs() < 1e-9, "{p:?}");
            assert!((p[2] - 1.1).abs() < 1e-9, "{p:?}");
        }
    }

    #[test]
    fn frame_names_come_from_the_snapshots_but_never_collide() {
        let latest = Latest {
            robot: Some(view("cam", &[])),
            human: Some(view("cam", &[])),
            ..Latest::default()
        };
        let names = FrameNames::of(&latest);
        assert_eq!(
            (names.robot.as_str(), names.human.as_str()),
            ("cam", "cam_human")
        );
        let names = FrameNames::of(&Latest::default());
        assert_eq!(
            (names.robot.as_str(), names.human.as_str()),
            (ROBOT_FRAME, HUMAN_FRAME)
        );
    }
}
