//! One Foxglove scene from the latest of everything: both views' objects
//! coloured by what the matcher decided, track ids, lines between the
//! pairs, the pointing ray, and the viewer's latest answer.

use std::collections::HashMap;

use foxglove::messages::{
    ArrowPrimitive, Color, CubePrimitive, CylinderPrimitive, KeyValuePair, LinePrimitive,
    SceneEntity, SceneUpdate, SpherePrimitive, TextPrimitive, Timestamp, line_primitive,
};
use vref_wire::{AnswerStatus, DecisionEntry, PointingRay, ReferenceAnswer};

use crate::frames::{FrameNames, Placement, WORLD_FRAME};
use crate::geometry::{IDENTITY, f64s, point, pose, rotation_between, unit, vector};
use crate::state::{Latest, View};

/// Ids of the scene's entities; each update replaces all of them.
pub mod entity {
    pub const ROBOT: &str = "robot/objects";
    pub const HUMAN: &str = "human/objects";
    pub const PAIRS: &str = "pairs";
    pub const RAY: &str = "ray";
    pub const ANSWER: &str = "answer";
    pub const HEADSET_HIGHLIGHT: &str = "answer/headset";
    pub const CAPTION: &str = "caption";
}

/// What the matcher concluded about one object, as coloured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Matched with confidence (`ok`).
    Matched,
    /// Below the threshold, with or without a partner.
    Ambiguous,
    /// The matcher says it has no partner in the other view.
    NoPartner,
    /// No decision covers it (none yet, or a robot object nobody chose).
    Undecided,
}

impl Outcome {
    pub fn color(self) -> Color {
        let (r, g, b) = match self {
            Outcome::Matched => (0.18, 0.75, 0.32),
            Outcome::Ambiguous => (1.0, 0.67, 0.0),
            Outcome::NoPartner => (0.86, 0.2, 0.2),
            Outcome::Undecided => (0.6, 0.62, 0.66),
        };
        Color { r, g, b, a: 1.0 }
    }

    pub fn name(self) -> &'static str {
        match self {
            Outcome::Matched => "matched",
            Outcome::Ambiguous => "ambiguous",
            Outcome::NoPartner => "no partner",
            Outcome::Undecided => "undecided",
        }
    }

    fn of_entry(e: &DecisionEntry) -> Self {
        match AnswerStatus::from_code(e.status) {
            Some(AnswerStatus::Ok) if e.flags & DecisionEntry::FLAG_PARTNER != 0 => {
                Outcome::Matched
            }
            Some(AnswerStatus::Ambiguous) => Outcome::Ambiguous,
            Some(AnswerStatus::NoMatch) => Outcome::NoPartner,
            _ => Outcome::Undecided,
        }
    }
}

fn with_alpha(c: Color, a: f64) -> Color {
    Color { a, ..c }
}

const TEXT: Color = Color {
    r: 0.95,
    g: 0.95,
    b: 0.95,
    a: 1.0,
};
const RAY: Color = Color {
    r: 0.35,
    g: 0.6,
    b: 1.0,
    a: 1.0,
};
const ANSWER: Color = Color {
    r: 0.3,
    g: 0.85,
    b: 1.0,
    a: 0.35,
};

/// Marker size: a share of the robot view's median nearest-neighbour
/// distance, so table tops and warehouse floors both read well.
pub fn marker_size(latest: &Latest) -> f64 {
    let view = latest
        .robot
        .as_ref()
        .filter(|v| v.objects.len() > 1)
        .or(latest.human.as_ref());
    let Some(view) = view.filter(|v| v.objects.len() > 1) else {
        return 0.05;
    };
    let mut nearest: Vec<f64> = view
        .objects
        .iter()
        .map(|(i, p)| {
            view.objects
                .iter()
                .filter(|(j, _)| j != i)
                .map(|(_, q)| distance(*p, *q))
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    nearest.sort_by(f64::total_cmp);
    (0.4 * nearest[nearest.len() / 2]).clamp(0.01, 0.25)
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The decision's outcome per human object and per robot object.
pub(crate) struct Outcomes<'a> {
    human: HashMap<u64, &'a DecisionEntry>,
    robot: HashMap<u64, Outcome>,
}

impl<'a> Outcomes<'a> {
    pub(crate) fn of(latest: &'a Latest) -> Self {
        let mut human = HashMap::new();
        let mut robot = HashMap::new();
        if let Some(d) = &latest.decision {
            for e in &d.entries {
                human.insert(e.human_track_id, e);
                if e.flags & DecisionEntry::FLAG_PARTNER != 0 {
                    robot.insert(e.robot_track_id, Outcome::of_entry(e));
                }
            }
        }
        Self { human, robot }
    }

    pub(crate) fn human(&self, id: u64) -> Outcome {
        self.human
            .get(&id)
            .map_or(Outcome::Undecided, |e| Outcome::of_entry(e))
    }

    pub(crate) fn robot(&self, id: u64) -> Outcome {
        self.robot.get(&id).copied().unwrap_or(Outcome::Undecided)
    }

    /// A human object's label: its id and what the matcher made of it.
    pub(crate) fn human_label(&self, id: u64) -> String {
        match self.human.get(&id) {
            Some(e) if e.flags & DecisionEntry::FLAG_PARTNER != 0 => {
                format!("H{id} -> R{} {:.2}", e.robot_track_id, e.confidence)
            }
            Some(e) => format!("H{id} {} {:.2}", self.human(id).name(), e.confidence),
            None => format!("H{id}"),
        }
    }
}

/// The whole scene at `time`. Every entity id is sent every time (empty
/// when there is nothing to draw), so an update replaces the last one.
pub fn scene(
    latest: &Latest,
    names: &FrameNames,
    placement: &Placement,
    time: Timestamp,
) -> SceneUpdate {
    let size = marker_size(latest);
    let outcomes = Outcomes::of(latest);
    let entity = |id: &str, frame: &str| SceneEntity {
        timestamp: Some(time),
        frame_id: frame.to_owned(),
        id: id.to_owned(),
        frame_locked: true,
        ..SceneEntity::default()
    };

    let mut robot = entity(entity::ROBOT, &names.robot);
    if let Some(view) = &latest.robot {
        for (id, p) in &view.objects {
            let outcome = outcomes.robot(*id);
            robot.spheres.push(SpherePrimitive {
                pose: Some(pose(*p, IDENTITY)),
                size: Some(vector([size; 3])),
                color: Some(outcome.color()),
            });
            robot.texts.push(label(*p, size, format!("R{id}")));
        }
        robot.metadata = vec![
            pair("objects", view.objects.len().to_string()),
            pair("sequence", view.sequence.to_string()),
        ];
    }

    let mut human = entity(entity::HUMAN, &names.human);
    if let Some(view) = &latest.human {
        for (id, p) in &view.objects {
            let outcome = outcomes.human(*id);
            human.cubes.push(CubePrimitive {
                pose: Some(pose(*p, IDENTITY)),
                size: Some(vector([size * 0.8; 3])),
                color: Some(with_alpha(outcome.color(), 0.85)),
            });
            human.texts.push(label(*p, size, outcomes.human_label(*id)));
        }
        human.metadata = vec![
            pair("objects", view.objects.len().to_string()),
            pair("sequence", view.sequence.to_string()),
        ];
    }

    let mut pairs = entity(entity::PAIRS, &names.robot);
    if let (Some(r), Some(h)) = (&latest.robot, &latest.human) {
        pairs
            .lines
            .extend(pair_lines(&outcomes, r, h, placement, size));
    }

    let mut ray = entity(entity::RAY, &names.human);
    if let Some(r) = &latest.ray {
        draw_ray(&mut ray, r, latest.human.as_ref(), size);
    }

    let mut answer = entity(entity::ANSWER, &names.robot);
    let mut headset = entity(entity::HEADSET_HIGHLIGHT, &names.human);
    if let Some(asked) = &latest.answer {
        draw_answer(&mut answer, &mut headset, &asked.answer, latest, size);
    }

    let mut caption = entity(entity::CAPTION, WORLD_FRAME);
    caption.texts.push(TextPrimitive {
        pose: Some(pose([0.0, 0.0, 3.0 * size], IDENTITY)),
        billboard: true,
        font_size: 14.0,
        scale_invariant: true,
        color: Some(TEXT),
        text: caption_text(latest, placement),
    });

    SceneUpdate {
        deletions: Vec::new(),
        entities: vec![robot, human, pairs, ray, answer, headset, caption],
    }
}

fn pair(key: &str, value: String) -> KeyValuePair {
    KeyValuePair {
        key: key.to_owned(),
        value,
    }
}

/// A track id floating above its object (camera y points down).
fn label(p: [f64; 3], size: f64, text: String) -> TextPrimitive {
    TextPrimitive {
        pose: Some(pose([p[0], p[1] - 0.9 * size, p[2]], IDENTITY)),
        billboard: true,
        font_size: 12.0,
        scale_invariant: true,
        color: Some(TEXT),
        text,
    }
}

/// One line per human object with a partner that both views show, from
/// the robot object to the human one as drawn: near zero length when the
/// motion explains the pair.
fn pair_lines(
    outcomes: &Outcomes<'_>,
    robot: &View,
    human: &View,
    placement: &Placement,
    size: f64,
) -> Vec<LinePrimitive> {
    let mut entries: Vec<&&DecisionEntry> = outcomes.human.values().collect();
    entries.sort_by_key(|e| e.human_track_id);
    entries
        .into_iter()
        .filter(|e| e.flags & DecisionEntry::FLAG_PARTNER != 0)
        .filter_map(|e| {
            let r = robot.position(e.robot_track_id)?;
            let h = placement.to_robot(human.position(e.human_track_id)?);
            Some(LinePrimitive {
                r#type: line_primitive::Type::LineStrip as i32,
                pose: Some(pose([0.0; 3], IDENTITY)),
                thickness: (0.15 * size).max(0.002),
                scale_invariant: false,
                points: vec![point(r), point(h)],
                color: Some(Outcome::of_entry(e).color()),
                colors: Vec::new(),
                indices: Vec::new(),
            })
        })
        .collect()
}

/// The ray as an arrow out to the farthest human object along it, inside
/// a faint cone of its half-angle.
fn draw_ray(entity: &mut SceneEntity, ray: &PointingRay, human: Option<&View>, size: f64) {
    let origin = f64s(ray.origin);
    let Some(d) = unit(f64s(ray.direction)) else {
        return;
    };
    if !origin.iter().all(|v| v.is_finite()) {
        return;
    }
    let reach = human
        .into_iter()
        .flat_map(|v| &v.objects)
        .map(|(_, p)| (0..3).map(|k| (p[k] - origin[k]) * d[k]).sum::<f64>())
        .fold(0.0, f64::max);
    let length = (reach * 1.1).clamp(0.3, 10.0);
    entity.arrows.push(ArrowPrimitive {
        pose: Some(pose(origin, rotation_between([1.0, 0.0, 0.0], d))),
        shaft_length: 0.85 * length,
        shaft_diameter: 0.2 * size,
        head_length: 0.15 * length,
        head_diameter: 0.5 * size,
        color: Some(RAY),
    });
    let angle = f64::from(ray.cone_half_angle);
    if angle.is_finite() && angle > 0.0 && angle < 1.5 {
        let width = 2.0 * length * angle.tan();
        let center = [0, 1, 2].map(|k| origin[k] + d[k] * length / 2.0);
        entity.cylinders.push(CylinderPrimitive {
            pose: Some(pose(center, rotation_between([0.0, 0.0, 1.0], d))),
            size: Some(vector([width, width, length])),
            bottom_scale: 0.0,
            top_scale: 1.0,
            color: Some(with_alpha(RAY, 0.12)),
        });
    }
    entity.metadata = vec![
        pair("sequence", ray.sequence.to_string()),
        pair("confidence", format!("{:.2}", ray.confidence)),
    ];
}

/// The answered robot object, ringed, with the answer in words; and where
/// the headset would highlight it, when the answer says.
fn draw_answer(
    robot: &mut SceneEntity,
    headset: &mut SceneEntity,
    a: &ReferenceAnswer,
    latest: &Latest,
    size: f64,
) {
    let status = a.status();
    let found = matches!(
        status,
        AnswerStatus::Ok | AnswerStatus::Ambiguous | AnswerStatus::Stale
    );
    let words = if found {
        format!(
            "answer: {} R{} {:.2}",
            status.name(),
            a.robot_track_id,
            a.confidence
        )
    } else {
        format!("answer: {}", status.name())
    };
    if found && a.position.iter().all(|v| v.is_finite()) {
        let p = f64s(a.position);
        robot.spheres.push(SpherePrimitive {
            pose: Some(pose(p, IDENTITY)),
            size: Some(vector([size * 2.2; 3])),
            color: Some(ANSWER),
        });
        robot
            .texts
            .push(label([p[0], p[1] - 1.2 * size, p[2]], size, words));
    } else if let Some(view) = &latest.robot {
        // Nothing to ring: say it above the robot's view.
        let top = view
            .objects
            .iter()
            .map(|(_, p)| *p)
            .fold(None, |best: Option<[f64; 3]>, p| match best {
                Some(b) if b[1] <= p[1] => Some(b),
                _ => Some(p),
            });
        if let Some(p) = top {
            robot
                .texts
                .push(label([p[0], p[1] - 3.0 * size, p[2]], size, words));
        }
    }
    if a.flags & ReferenceAnswer::FLAG_HUMAN_POSITION != 0
        && a.human_frame_position.iter().all(|v| v.is_finite())
    {
        let p = f64s(a.human_frame_position);
        headset.cubes.push(CubePrimitive {
            pose: Some(pose(p, IDENTITY)),
            size: Some(vector([size * 1.8; 3])),
            color: Some(ANSWER),
        });
        let how = if a.flags & ReferenceAnswer::FLAG_HUMAN_POSITION_FROM_MOTION != 0 {
            "headset highlight (via motion)"
        } else {
            "headset highlight"
        };
        headset.texts.push(label(p, size * 2.0, how.to_owned()));
    }
    robot.metadata = vec![
        pair("status", status.name().to_owned()),
        pair("robot_track_id", a.robot_track_id.to_string()),
        pair("confidence", format!("{:.3}", a.confidence)),
    ];
}

fn caption_text(latest: &Latest, placement: &Placement) -> String {
    // Whether each view says which way is up: the matcher's methods use
    // it only when both do.
    let count = |view: &Option<View>| match view {
        Some(v) if v.up.is_some() => format!("{} objects, up known", v.objects.len()),
        Some(v) => format!("{} objects", v.objects.len()),
        None => "0 objects".to_owned(),
    };
    let views = format!(
        "robot {}, headset {}",
        count(&latest.robot),
        count(&latest.human)
    );
    let decision = match &latest.decision {
        Some(d) => {
            let matched = d
                .entries
                .iter()
                .filter(|e| Outcome::of_entry(e) == Outcome::Matched)
                .count();
            format!(
                "{} solve #{}: {matched} of {} matched{}",
                d.method(),
                d.header.solve_index,
                d.entries.len(),
                residuals(d)
            )
        }
        None => "no decision published".to_owned(),
    };
    let motion = if placement.has_motion() {
        "headset placed by the estimated motion"
    } else {
        "no motion estimate: headset view drawn beside"
    };
    format!("vref | {views} | {decision} | {motion}")
}

/// The motion's residual statistics, where the decision carries them:
/// its pairs' median squared residual in units of the stated errors and
/// the largest, so that a motion that fits its pairs worse than the
/// sensors say they err is plain to see.
fn residuals(d: &vref_wire::ipc::Decision) -> String {
    if d.header.flags & vref_wire::DecisionHeader::FLAG_RESIDUALS == 0 {
        return String::new();
    }
    let largest = d
        .entries
        .iter()
        .filter(|e| e.flags & DecisionEntry::FLAG_RESIDUAL != 0)
        .map(|e| e.residual)
        .fold(f32::NEG_INFINITY, f32::max);
    format!(
        ", residual median {:.1} max {:.1} (stated errors\u{b2})",
        d.header.residual_median, largest
    )
}

#[cfg(test)]
mod tests {
    use vref_wire::DecisionHeader;
    use vref_wire::ipc::Decision;

    use super::*;
    use crate::state::Asked;

    fn view(name: &str, objects: &[(u64, [f64; 3])]) -> View {
        View {
            frame_name: name.to_owned(),
            sequence: 5,
            timestamp_ns: 0,
            objects: objects.to_vec(),
            up: None,
        }
    }

    fn entry(human: u64, robot: Option<u64>, status: AnswerStatus) -> DecisionEntry {
        DecisionEntry {
            human_track_id: human,
            robot_track_id: robot.unwrap_or(0),
            confidence: 0.9,
            status: status as u32,
            flags: if robot.is_some() {
                DecisionEntry::FLAG_PARTNER
            } else {
                0
            },
            residual: 0.0,
        }
    }

    fn latest(decision: bool) -> Latest {
        let robot = view(
            "robot_camera",
            &[
                (10, [0.0, 0.0, 1.0]),
                (20, [0.2, 0.0, 1.0]),
                (30, [0.4, 0.0, 1.0]),
            ],
        );
        let human = view(
            "headset_camera",
            &[
                (1, [0.0, 0.0, 0.5]),
                (2, [0.2, 0.0, 0.5]),
                (3, [0.4, 0.0, 0.5]),
            ],
        );
        let decision = decision.then(|| Decision {
            header: DecisionHeader {
                solve_index: 4,
                method: *b"rigid\0\0\0\0\0\0\0\0\0\0\0",
                ..DecisionHeader::default()
            },
            entries: vec![
                entry(1, Some(10), AnswerStatus::Ok),
                entry(2, Some(20), AnswerStatus::Ambiguous),
                entry(3, None, AnswerStatus::NoMatch),
            ],
        });
        Latest {
            robot: Some(robot),
            human: Some(human),
            decision,
            ..Latest::default()
        }
    }

    fn draw(latest: &Latest) -> SceneUpdate {
        let names = FrameNames::of(latest);
        let placement = Placement::of(latest, 0.1);
        scene(latest, &names, &placement, Timestamp::new(10, 0))
    }

    fn find<'a>(update: &'a SceneUpdate, id: &str) -> &'a SceneEntity {
        update.entities.iter().find(|e| e.id == id).unwrap()
    }

    #[test]
    fn objects_are_coloured_by_the_decision_and_labelled_by_track_id() {
        let update = draw(&latest(true));
        let robot = find(&update, entity::ROBOT);
        assert_eq!(robot.frame_id, "robot_camera");
        let colours: Vec<Color> = robot.spheres.iter().map(|s| s.color.unwrap()).collect();
        assert_eq!(
            colours,
            [
                Outcome::Matched.color(),
                Outcome::Ambiguous.color(),
                // Nobody chose robot object 30.
                Outcome::Undecided.color()
            ]
        );
        let texts: Vec<&str> = robot.texts.iter().map(|t| t.text.as_str()).collect();
        assert_eq!(texts, ["R10", "R20", "R30"]);

        let human = find(&update, entity::HUMAN);
        assert_eq!(human.frame_id, "headset_camera");
        let colours: Vec<Color> = human
            .cubes
            .iter()
            .map(|c| with_alpha(c.color.unwrap(), 1.0))
            .collect();
        assert_eq!(
            colours,
            [
                Outcome::Matched.color(),
                Outcome::Ambiguous.color(),
                Outcome::NoPartner.color()
            ]
        );
        assert_eq!(human.texts[0].text, "H1 -> R10 0.90");
        assert_eq!(human.texts[2].text, "H3 no partner 0.90");
    }

    #[test]
    fn lines_join_the_pairs_as_drawn() {
        let l = latest(true);
        let update = draw(&l);
        let pairs = find(&update, entity::PAIRS);
        // Human 3 has no partner: two lines.
        assert_eq!(pairs.lines.len(), 2);
        let placement = Placement::of(&l, 0.1);
        let first = &pairs.lines[0];
        assert_eq!(first.points[0], point([0.0, 0.0, 1.0]));
        assert_eq!(first.points[1], point(placement.to_robot([0.0, 0.0, 0.5])));
        assert_eq!(first.color, Some(Outcome::Matched.color()));
    }

    #[test]
    fn without_a_decision_objects_and_rays_are_still_drawn() {
        let mut l = latest(false);
        l.ray = Some(PointingRay {
            session: 1,
            sequence: 3,
            timestamp_ns: 0,
            origin: [0.0, 0.0, 0.0],
            direction: [0.0, 0.0, 2.0],
            cone_half_angle: 0.1,
            confidence: 0.8,
            schema_version: 2,
            reserved: 0,
        });
        let update = draw(&l);
        assert_eq!(update.entities.len(), 7);
        let robot = find(&update, entity::ROBOT);
        assert!(
            robot
                .spheres
                .iter()
                .all(|s| s.color == Some(Outcome::Undecided.color()))
        );
        assert!(find(&update, entity::PAIRS).lines.is_empty());
        let ray = find(&update, entity::RAY);
        assert_eq!(ray.frame_id, "headset_camera");
        let arrow = ray.arrows[0];
        // Out past the farthest human object along the ray (0.5 m).
        assert!((arrow.shaft_length + arrow.head_length - 0.55).abs() < 1e-9);
        // The arrow's +x is turned onto the ray's direction (+z).
        let q = arrow.pose.unwrap().orientation.unwrap();
        let x = crate::geometry::rotate(&q, [1.0, 0.0, 0.0]);
        assert!((x[2] - 1.0).abs() < 1e-9, "{x:?}");
        assert_eq!(ray.cylinders.len(), 1);
        let caption = &find(&update, entity::CAPTION).texts[0].text;
        assert!(caption.contains("no decision"), "{caption}");
        assert!(!caption.contains("up known"), "{caption}");
    }

    #[test]
    fn the_caption_gives_the_motion_s_residuals_where_the_decision_has_them() {
        let mut l = latest(true);
        let caption = |l: &Latest| find(&draw(l), entity::CAPTION).texts[0].text.clone();
        assert!(!caption(&l).contains("residual"), "{}", caption(&l));
        if let Some(d) = &mut l.decision {
            d.header.flags |= DecisionHeader::FLAG_RESIDUALS;
            d.header.residual_median = 2.4;
            d.entries[0].flags |= DecisionEntry::FLAG_RESIDUAL;
            d.entries[0].residual = 9.25;
        }
        let text = caption(&l);
        assert!(text.contains("residual median 2.4 max 9.2"), "{text}");
    }

    #[test]
    fn the_caption_says_which_views_know_which_way_is_up() {
        let mut l = latest(false);
        if let Some(human) = &mut l.human {
            human.up = Some([0.0, -1.0, 0.0]);
        }
        let update = draw(&l);
        let caption = &find(&update, entity::CAPTION).texts[0].text;
        assert!(caption.contains("headset 3 objects, up known"), "{caption}");
        assert!(!caption.contains("robot 3 objects, up known"), "{caption}");
    }

    #[test]
    fn the_answer_is_ringed_and_shown_where_the_headset_would_highlight_it() {
        let mut l = latest(true);
        let mut a = ReferenceAnswer::empty(1, AnswerStatus::Ok);
        a.robot_track_id = 20;
        a.position = [0.2, 0.0, 1.0];
        a.confidence = 0.75;
        a.human_frame_position = [0.2, 0.0, 0.5];
        a.flags =
            ReferenceAnswer::FLAG_HUMAN_POSITION | ReferenceAnswer::FLAG_HUMAN_POSITION_FROM_MOTION;
        l.answer = Some(Asked {
            answer: a,
            round_trip_us: 100,
            received_ns: 0,
        });
        let update = draw(&l);
        let answer = find(&update, entity::ANSWER);
        assert_eq!(answer.spheres.len(), 1);
        assert_eq!(answer.texts[0].text, "answer: ok R20 0.75");
        let headset = find(&update, entity::HEADSET_HIGHLIGHT);
        assert_eq!(headset.frame_id, "headset_camera");
        assert_eq!(headset.cubes.len(), 1);
        assert!(headset.texts[0].text.contains("via motion"));

        // A no-match answer rings nothing and says so.
        l.answer = Some(Asked {
            answer: ReferenceAnswer::empty(2, AnswerStatus::NoMatch),
            round_trip_us: 100,
            received_ns: 0,
        });
        let update = draw(&l);
        let answer = find(&update, entity::ANSWER);
        assert!(answer.spheres.is_empty());
        assert_eq!(answer.texts[0].text, "answer: no_match");
        assert!(find(&update, entity::HEADSET_HIGHLIGHT).cubes.is_empty());
    }

    #[test]
    fn markers_scale_with_the_spacing_of_the_objects() {
        let l = latest(false);
        assert!((marker_size(&l) - 0.08).abs() < 1e-9);
        assert_eq!(marker_size(&Latest::default()), 0.05);
    }
}
