//! What the matcher decided, as one `visualization_msgs/MarkerArray`:
//! both views' objects coloured by the decision (vref view's colours),
//! lines between the pairs, the latest answer highlighted, and the
//! headset's pose from the estimated motion. Pure.
//!
//! The human view's objects are drawn in the robot camera's frame,
//! mapped through the matcher's motion, when it has one: RViz then needs
//! no transform for the headset. Without a motion they are drawn in the
//! headset frame id, and pairs (which would cross frames) are left out.

use vref_view::{Outcome, View};
use vref_wire::ipc::Decision;
use vref_wire::{AnswerStatus, DecisionEntry, DecisionHeader, ReferenceAnswer};

use crate::msg::{
    ColorRgba, Duration, Header, Marker, MarkerArray, Point, Pose, PoseStamped, Quaternion, Time,
};

/// Diameter of an object's sphere, metres.
pub const OBJECT_SIZE: f64 = 0.04;
/// How long a marker stays if no newer array replaces it (seconds):
/// RViz clears what a stopped vref-ros2 left behind.
pub const LIFETIME_S: i32 = 2;

/// Namespaces, so that RViz's marker display lists each kind on its own.
pub const NS_ROBOT: &str = "robot";
pub const NS_HUMAN: &str = "human";
pub const NS_PAIRS: &str = "pairs";
pub const NS_ANSWER: &str = "answer";

/// What one array is drawn from.
#[derive(Debug, Clone, Copy, Default)]
pub struct Scene<'a> {
    pub robot: Option<&'a View>,
    pub human: Option<&'a View>,
    pub decision: Option<&'a Decision>,
    pub answer: Option<&'a ReferenceAnswer>,
}

/// The frame ids markers are stamped with.
#[derive(Debug, Clone, Copy)]
pub struct Frames<'a> {
    pub robot: &'a str,
    pub headset: &'a str,
}

/// The matcher's motion (human camera frame to robot camera frame), if
/// the decision has one.
pub fn motion(decision: &Decision) -> Option<([f64; 9], [f64; 3])> {
    let h: &DecisionHeader = &decision.header;
    if h.flags & DecisionHeader::FLAG_MOTION == 0 {
        return None;
    }
    let r = h.rotation.map(f64::from);
    let t = h.translation.map(f64::from);
    (r.iter().chain(&t).all(|v| v.is_finite())).then_some((r, t))
}

fn apply(r: &[f64; 9], t: &[f64; 3], p: [f64; 3]) -> [f64; 3] {
    [
        r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + t[0],
        r[3] * p[0] + r[4] * p[1] + r[5] * p[2] + t[1],
        r[6] * p[0] + r[7] * p[1] + r[8] * p[2] + t[2],
    ]
}

fn outcome_of(e: &DecisionEntry) -> Outcome {
    match AnswerStatus::from_code(e.status) {
        Some(AnswerStatus::Ok) if e.flags & DecisionEntry::FLAG_PARTNER != 0 => Outcome::Matched,
        Some(AnswerStatus::Ambiguous) => Outcome::Ambiguous,
        Some(AnswerStatus::NoMatch) => Outcome::NoPartner,
        _ => Outcome::Undecided,
    }
}

fn colour(outcome: Outcome) -> ColorRgba {
    let c = outcome.color();
    ColorRgba {
        r: c.r as f32,
        g: c.g as f32,
        b: c.b as f32,
        a: 1.0,
    }
}

fn sphere(header: &Header, ns: &str, id: i32, at: [f64; 3], size: f64, c: ColorRgba) -> Marker {
    Marker {
        header: header.clone(),
        ns: ns.to_owned(),
        id,
        kind: Marker::SPHERE,
        action: Marker::ADD,
        pose: Pose {
            position: at.into(),
            orientation: Quaternion::default(),
        },
        scale: [size; 3].into(),
        color: c,
        lifetime: Duration {
            sec: LIFETIME_S,
            nanosec: 0,
        },
        ..Marker::default()
    }
}

/// The whole array: a DELETEALL first (objects come and go between
/// snapshots, and ids are not stable), then the objects, pairs, answer.
pub fn markers(scene: &Scene<'_>, frames: Frames<'_>, stamp: Time) -> MarkerArray {
    let robot_header = Header {
        stamp,
        frame_id: frames.robot.to_owned(),
    };
    let mut out = vec![Marker {
        header: robot_header.clone(),
        action: Marker::DELETEALL,
        ..Marker::default()
    }];
    let entries: &[DecisionEntry] = scene.decision.map_or(&[], |d| &d.entries);
    let motion = scene.decision.and_then(motion);
    if let Some(robot) = scene.robot {
        // The robot's objects as of the camera frame they were seen in:
        // its stamp (the colour image's), for TF and for telling frames
        // apart (`vref bench ros2` times each frame's markers by it).
        let seen = Header {
            stamp: Time::from_ns(robot.timestamp_ns),
            frame_id: frames.robot.to_owned(),
        };
        for (k, (id, p)) in robot.objects.iter().enumerate() {
            let outcome = entries
                .iter()
                .find(|e| e.robot_track_id == *id && e.flags & DecisionEntry::FLAG_PARTNER != 0)
                .map_or(Outcome::Undecided, outcome_of);
            out.push(sphere(
                &seen,
                NS_ROBOT,
                k as i32,
                *p,
                OBJECT_SIZE,
                colour(outcome),
            ));
        }
    }
    if let Some(human) = scene.human {
        let header = match motion {
            Some(_) => robot_header.clone(),
            None => Header {
                stamp,
                frame_id: frames.headset.to_owned(),
            },
        };
        let mut pairs = Vec::new();
        for (k, (id, p)) in human.objects.iter().enumerate() {
            let entry = entries.iter().find(|e| e.human_track_id == *id);
            let at = motion.map_or(*p, |(r, t)| apply(&r, &t, *p));
            out.push(sphere(
                &header,
                NS_HUMAN,
                k as i32,
                at,
                0.75 * OBJECT_SIZE,
                colour(entry.map_or(Outcome::Undecided, outcome_of)),
            ));
            if motion.is_some()
                && let Some(e) = entry
                && e.flags & DecisionEntry::FLAG_PARTNER != 0
                && let Some(q) = scene.robot.and_then(|r| r.position(e.robot_track_id))
            {
                pairs.push(Point::from(at));
                pairs.push(Point::from(q));
            }
        }
        if !pairs.is_empty() {
            out.push(Marker {
                kind: Marker::LINE_LIST,
                points: pairs,
                scale: [0.004, 0.0, 0.0].into(),
                color: colour(Outcome::Matched),
                ..sphere(
                    &robot_header,
                    NS_PAIRS,
                    0,
                    [0.0; 3],
                    0.0,
                    ColorRgba::default(),
                )
            });
        }
    }
    if let Some(a) = scene.answer
        && a.status() == AnswerStatus::Ok
    {
        let at = a.position.map(f64::from);
        if at.iter().all(|v| v.is_finite()) {
            let highlight = ColorRgba {
                r: 0.2,
                g: 0.6,
                b: 1.0,
                a: 0.5,
            };
            out.push(sphere(
                &robot_header,
                NS_ANSWER,
                0,
                at,
                2.0 * OBJECT_SIZE,
                highlight,
            ));
        }
    }
    MarkerArray { markers: out }
}

/// The headset camera's pose in the robot camera's frame: the motion
/// maps headset coordinates to robot ones, so its translation is the
/// headset's origin and its rotation the headset's axes.
pub fn headset_pose(decision: &Decision, robot_frame: &str, stamp: Time) -> Option<PoseStamped> {
    let (r, t) = motion(decision)?;
    let q = vref_view::quaternion_of(&r);
    Some(PoseStamped {
        header: Header {
            stamp,
            frame_id: robot_frame.to_owned(),
        },
        pose: Pose {
            position: t.into(),
            orientation: Quaternion {
                x: q.x,
                y: q.y,
                z: q.z,
                w: q.w,
            },
        },
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
    use super::*;
    use vref_wire::SCHEMA_VERSION;

    fn view(objects: &[(u64, [f64; 3])]) -> View {
        View {
            objects: objects.to_vec(),
            ..View::default()
        }
    }

    fn decision(motion: bool, entries: Vec<DecisionEntry>) -> Decision {
        let mut header = DecisionHeader {
            schema_version: SCHEMA_VERSION,
            pair_count: entries.len() as u32,
            ..DecisionHeader::default()
        };
        if motion {
            header.flags = DecisionHeader::FLAG_MOTION;
            // A half turn about z and a shift along x.
            header.rotation = [-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0];
            header.translation = [1.0, 0.0, 0.0];
        }
        Decision { header, entries }
    }

    fn pair(human: u64, robot: u64, status: AnswerStatus) -> DecisionEntry {
        DecisionEntry {
            human_track_id: human,
            robot_track_id: robot,
            confidence: 0.9,
            status: status as u32,
            flags: DecisionEntry::FLAG_PARTNER,
            residual: 0.0,
        }
    }

    const FRAMES: Frames<'static> = Frames {
        robot: "cam",
        headset: "headset",
    };

    #[test]
    fn objects_are_coloured_by_the_decision_and_paired_in_the_robot_frame() {
        let robot = view(&[(10, [0.0, 0.0, 1.0]), (11, [0.1, 0.0, 1.0])]);
        let human = view(&[(1, [1.0, 0.0, 1.0])]);
        let d = decision(true, vec![pair(1, 10, AnswerStatus::Ok)]);
        let scene = Scene {
            robot: Some(&robot),
            human: Some(&human),
            decision: Some(&d),
            answer: None,
        };
        let a = markers(&scene, FRAMES, Time::default());
        assert_eq!(a.markers[0].action, Marker::DELETEALL);
        let robot_m: Vec<_> = a.markers.iter().filter(|m| m.ns == NS_ROBOT).collect();
        assert_eq!(robot_m.len(), 2);
        assert_eq!(robot_m[0].color, colour(Outcome::Matched));
        assert_eq!(robot_m[1].color, colour(Outcome::Undecided));
        let human_m = a.markers.iter().find(|m| m.ns == NS_HUMAN).unwrap();
        // (1, 0, 1) turned half about z is (-1, 0, 1), plus (1, 0, 0).
        assert_eq!(human_m.header.frame_id, "cam");
        assert_eq!(human_m.pose.position, Point::from([0.0, 0.0, 1.0]));
        let pairs = a.markers.iter().find(|m| m.ns == NS_PAIRS).unwrap();
        assert_eq!(pairs.points.len(), 2);
    }

    #[test]
    fn robot_objects_carry_their_camera_frames_stamp_and_the_rest_the_arrays() {
        let robot = View {
            timestamp_ns: 1_700_000_000_123_456_789,
            ..view(&[(10, [0.0, 0.0, 1.0])])
        };
        let scene = Scene {
            robot: Some(&robot),
            human: None,
            decision: None,
            answer: None,
        };
        let made = Time { sec: 5, nanosec: 6 };
        let a = markers(&scene, FRAMES, made);
        assert_eq!(a.markers[0].header.stamp, made);
        let robot_m = a.markers.iter().find(|m| m.ns == NS_ROBOT).unwrap();
        assert_eq!(
            robot_m.header.stamp,
            Time {
                sec: 1_700_000_000,
                nanosec: 123_456_789
            }
        );
    }

    #[test]
    fn without_a_motion_the_human_view_stays_in_its_frame_and_has_no_pairs() {
        let robot = view(&[(10, [0.0, 0.0, 1.0])]);
        let human = view(&[(1, [1.0, 0.0, 1.0])]);
        let d = decision(false, vec![pair(1, 10, AnswerStatus::Ambiguous)]);
        let scene = Scene {
            robot: Some(&robot),
            human: Some(&human),
            decision: Some(&d),
            answer: None,
        };
        let a = markers(&scene, FRAMES, Time::default());
        let human_m = a.markers.iter().find(|m| m.ns == NS_HUMAN).unwrap();
        assert_eq!(human_m.header.frame_id, "headset");
        assert_eq!(human_m.color, colour(Outcome::Ambiguous));
        assert!(a.markers.iter().all(|m| m.ns != NS_PAIRS));
        assert!(headset_pose(&d, "cam", Time::default()).is_none());
    }

    #[test]
    fn the_headset_pose_is_the_motion() {
        let d = decision(true, Vec::new());
        let p = headset_pose(&d, "cam", Time::default()).unwrap();
        assert_eq!(p.pose.position, Point::from([1.0, 0.0, 0.0]));
        // A half turn about z: (0, 0, +-1, 0).
        assert!((p.pose.orientation.z.abs() - 1.0).abs() < 1e-9);
        assert!(p.pose.orientation.w.abs() < 1e-9);
    }
}
