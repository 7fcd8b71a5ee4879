//! The cameras' images for Foxglove's image panel, when the feeds measure
//! images (`--source bop:DIR`): each camera's colour image as the dataset
//! holds it (`foxglove.CompressedImage`, JPEG or PNG bytes, never
//! re-encoded), its intrinsics (`foxglove.CameraCalibration`, so that
//! panels can project into it) and every measured object's mask outline
//! coloured by the matcher's decision, with its track id
//! (`foxglove.ImageAnnotations`). The conversions here are pure; loading
//! a dataset's images is [`crate::load_bop_images`].

use std::collections::HashMap;

use foxglove::messages::{
    CameraCalibration, Color, CompressedImage, ImageAnnotations, KeyValuePair, Point2,
    PointsAnnotation, TextAnnotation, Timestamp, points_annotation,
};
use vref_scene::Side;

use crate::scene::Outcomes;
use crate::state::{Latest, View};

/// One object's mask as drawn: its track id and its outline's polygons
/// (pixel corners, `vref_perception::outline_polygons`).
#[derive(Debug, Clone, PartialEq)]
pub struct ImageObject {
    pub track_id: u64,
    pub polygons: Vec<Vec<[u32; 2]>>,
}

/// One camera's image of one scene.
#[derive(Clone, PartialEq)]
pub struct CameraImage {
    /// `jpeg` or `png`, as Foxglove names them.
    pub format: &'static str,
    /// The file's bytes.
    pub data: Vec<u8>,
    pub width: u32,
    pub height: u32,
    /// Row-major `[fx 0 cx; 0 fy cy; 0 0 1]`.
    pub k: [f64; 9],
    /// The objects the feed publishes for this image, in track-id order.
    pub objects: Vec<ImageObject>,
}

impl std::fmt::Debug for CameraImage {
    // The image's bytes say nothing to a reader.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CameraImage")
            .field("format", &self.format)
            .field("bytes", &self.data.len())
            .field("width", &self.width)
            .field("height", &self.height)
            .field("k", &self.k)
            .field("objects", &self.objects.len())
            .finish()
    }
}

/// Both cameras' images of one scene.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneImages {
    /// `table/000003`.
    pub name: String,
    pub robot: CameraImage,
    pub human: CameraImage,
}

impl SceneImages {
    pub fn camera(&self, side: Side) -> &CameraImage {
        match side {
            Side::Robot => &self.robot,
            Side::Human => &self.human,
        }
    }
}

/// Every scene's images, and which scene each track id belongs to.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Images {
    scenes: Vec<SceneImages>,
    robot_ids: HashMap<u64, usize>,
    human_ids: HashMap<u64, usize>,
}

impl Images {
    pub fn new(scenes: Vec<SceneImages>) -> Self {
        let index = |side: Side| {
            scenes
                .iter()
                .enumerate()
                .flat_map(|(k, s)| s.camera(side).objects.iter().map(move |o| (o.track_id, k)))
                .collect()
        };
        Self {
            robot_ids: index(Side::Robot),
            human_ids: index(Side::Human),
            scenes,
        }
    }

    pub fn scenes(&self) -> &[SceneImages] {
        &self.scenes
    }

    /// The scene a snapshot shows: the one whose image holds its first
    /// object that any image holds. The feeds give every scene's objects
    /// ids of their own, so a snapshot's ids say which scene is live with
    /// no clock or schedule to agree on; a snapshot with no known object
    /// (empty, or from another source) shows none.
    pub fn scene_of(&self, side: Side, view: &View) -> Option<usize> {
        let ids = match side {
            Side::Robot => &self.robot_ids,
            Side::Human => &self.human_ids,
        };
        view.objects.iter().find_map(|(id, _)| ids.get(id).copied())
    }
}

/// The image as logged: the file's own bytes.
pub fn compressed_image(camera: &CameraImage, frame_id: &str, time: Timestamp) -> CompressedImage {
    CompressedImage {
        timestamp: Some(time),
        frame_id: frame_id.to_owned(),
        data: camera.data.clone().into(),
        format: camera.format.to_owned(),
    }
}

/// The camera as Foxglove describes one: a pinhole without distortion
/// (BOP's images are undistorted), so `P` is `K` with a zero column.
pub fn calibration(camera: &CameraImage, frame_id: &str, time: Timestamp) -> CameraCalibration {
    let k = camera.k;
    CameraCalibration {
        timestamp: Some(time),
        frame_id: frame_id.to_owned(),
        width: camera.width,
        height: camera.height,
        distortion_model: "plumb_bob".to_owned(),
        d: vec![0.0; 5],
        k: k.to_vec(),
        r: vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        p: vec![
            k[0], k[1], k[2], 0.0, k[3], k[4], k[5], 0.0, k[6], k[7], k[8], 0.0,
        ],
    }
}

const TEXT_BACKGROUND: Color = Color {
    r: 0.0,
    g: 0.0,
    b: 0.0,
    a: 0.55,
};
const FONT_SIZE: f64 = 12.0;

/// Each object's mask outline, one `LINE_LIST` annotation per object (all
/// its polygons' sides, so that holes and fragments stay one object),
/// coloured as the scene colours it, with its label at the outline's top
/// left: `R<id>` for robot objects, `H<id> -> R<id> confidence` for
/// headset ones. Each annotation carries `track_id` in its metadata.
pub fn annotations(
    camera: &CameraImage,
    side: Side,
    latest: &Latest,
    scene_name: &str,
    time: Timestamp,
) -> ImageAnnotations {
    let outcomes = Outcomes::of(latest);
    let mut out = ImageAnnotations {
        timestamp: Some(time),
        metadata: vec![KeyValuePair {
            key: "scene".to_owned(),
            value: scene_name.to_owned(),
        }],
        ..ImageAnnotations::default()
    };
    for object in &camera.objects {
        let id = object.track_id;
        let (outcome, text) = match side {
            Side::Robot => (outcomes.robot(id), format!("R{id}")),
            Side::Human => (outcomes.human(id), outcomes.human_label(id)),
        };
        let point = |[x, y]: [u32; 2]| Point2 {
            x: f64::from(x),
            y: f64::from(y),
        };
        let points: Vec<Point2> = object
            .polygons
            .iter()
            .flat_map(|polygon| {
                let n = polygon.len();
                (0..n).flat_map(move |i| [polygon[i], polygon[(i + 1) % n]])
            })
            .map(point)
            .collect();
        let top_left = object.polygons.iter().flatten().fold(
            None,
            |best: Option<[u32; 2]>, &[x, y]| match best {
                Some([bx, by]) => Some([bx.min(x), by.min(y)]),
                None => Some([x, y]),
            },
        );
        let metadata = vec![KeyValuePair {
            key: "track_id".to_owned(),
            value: id.to_string(),
        }];
        out.points.push(PointsAnnotation {
            timestamp: Some(time),
            r#type: points_annotation::Type::LineList as i32,
            points,
            outline_color: Some(outcome.color()),
            outline_colors: Vec::new(),
            fill_color: None,
            thickness: 2.0,
            metadata: metadata.clone(),
        });
        if let Some([x, y]) = top_left {
            // The text's origin is its bottom left: just above the
            // outline, or inside it at the image's top edge.
            let y = (f64::from(y) - 3.0).max(FONT_SIZE);
            out.texts.push(TextAnnotation {
                timestamp: Some(time),
                position: Some(Point2 { x: f64::from(x), y }),
                text,
                font_size: FONT_SIZE,
                text_color: Some(outcome.color()),
                background_color: Some(TEXT_BACKGROUND),
                metadata,
            });
        }
    }
    out
}

/// What the annotations of a camera show, to log them again only when it
/// changes: the scene and each object's colour and label.
pub(crate) fn annotation_key(camera: &CameraImage, side: Side, latest: &Latest) -> Vec<String> {
    let outcomes = Outcomes::of(latest);
    camera
        .objects
        .iter()
        .map(|o| match side {
            Side::Robot => format!("{} {:?}", o.track_id, outcomes.robot(o.track_id)),
            Side::Human => outcomes.human_label(o.track_id),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use vref_wire::ipc::Decision;
    use vref_wire::{AnswerStatus, DecisionEntry, DecisionHeader};

    use super::*;
    use crate::scene::Outcome;

    fn square(id: u64, x: u32, y: u32) -> ImageObject {
        ImageObject {
            track_id: id,
            polygons: vec![vec![[x, y], [x + 4, y], [x + 4, y + 4], [x, y + 4]]],
        }
    }

    fn camera(objects: Vec<ImageObject>) -> CameraImage {
        CameraImage {
            format: "png",
            data: vec![1, 2, 3],
            width: 64,
            height: 48,
            k: [500.0, 0.0, 32.0, 0.0, 501.0, 24.0, 0.0, 0.0, 1.0],
            objects,
        }
    }

    fn view(ids: &[u64]) -> View {
        View {
            objects: ids.iter().map(|&i| (i, [0.0, 0.0, 1.0])).collect(),
            ..View::default()
        }
    }

    fn time() -> Timestamp {
        Timestamp::new(1, 2)
    }

    #[test]
    fn a_snapshot_names_its_scene_by_its_track_ids() {
        let scene = |name: &str, r: u64, h: u64| SceneImages {
            name: name.to_owned(),
            robot: camera(vec![square(r, 0, 0)]),
            human: camera(vec![square(h, 0, 0)]),
        };
        let images = Images::new(vec![scene("a", 1001, 2001), scene("b", 101_001, 102_001)]);
        assert_eq!(images.scene_of(Side::Robot, &view(&[101_001])), Some(1));
        assert_eq!(images.scene_of(Side::Human, &view(&[2001])), Some(0));
        // An unknown id is passed over; a robot id is not a human one.
        assert_eq!(images.scene_of(Side::Robot, &view(&[7, 1001])), Some(0));
        assert_eq!(images.scene_of(Side::Human, &view(&[1001])), None);
        assert_eq!(images.scene_of(Side::Robot, &view(&[])), None);
    }

    #[test]
    fn the_image_is_the_files_bytes_and_the_calibration_its_intrinsics() {
        let c = camera(Vec::new());
        let image = compressed_image(&c, "robot_camera", time());
        assert_eq!(
            (&image.data[..], image.format.as_str()),
            (&[1u8, 2, 3][..], "png")
        );
        assert_eq!(image.frame_id, "robot_camera");
        let cal = calibration(&c, "robot_camera", time());
        assert_eq!((cal.width, cal.height), (64, 48));
        assert_eq!(cal.k, c.k.to_vec());
        assert_eq!(cal.p[..4], [500.0, 0.0, 32.0, 0.0]);
        assert_eq!(cal.p[4..8], [0.0, 501.0, 24.0, 0.0]);
        assert_eq!(cal.frame_id, "robot_camera");
    }

    #[test]
    fn each_object_is_one_outline_coloured_by_the_decision_with_its_id() {
        let c = camera(vec![square(2001, 2, 3), square(2002, 20, 0)]);
        let mut latest = Latest::default();
        let undecided = annotations(&c, Side::Human, &latest, "s", time());
        assert_eq!(undecided.points.len(), 2);
        assert_eq!(undecided.texts.len(), 2);
        let first = &undecided.points[0];
        assert_eq!(
            first.r#type,
            points_annotation::Type::LineList as i32,
            "one annotation per object, holes and all"
        );
        // Four sides, two points each, in order round the square.
        let xy: Vec<(f64, f64)> = first.points.iter().map(|p| (p.x, p.y)).collect();
        assert_eq!(
            xy,
            vec![
                (2.0, 3.0),
                (6.0, 3.0),
                (6.0, 3.0),
                (6.0, 7.0),
                (6.0, 7.0),
                (2.0, 7.0),
                (2.0, 7.0),
                (2.0, 3.0)
            ]
        );
        assert_eq!(first.outline_color, Some(Outcome::Undecided.color()));
        assert_eq!(undecided.texts[0].text, "H2001");
        assert_eq!(undecided.texts[0].metadata[0].value, "2001");
        // At the image's top edge the label stays on the image.
        assert!(undecided.texts[1].position.unwrap().y >= FONT_SIZE);

        latest.decision = Some(Decision {
            header: DecisionHeader::default(),
            entries: vec![DecisionEntry {
                human_track_id: 2001,
                robot_track_id: 1007,
                confidence: 0.93,
                status: AnswerStatus::Ok as u32,
                flags: DecisionEntry::FLAG_PARTNER,
                residual: 0.0,
            }],
        });
        let decided = annotations(&c, Side::Human, &latest, "s", time());
        assert_eq!(
            decided.points[0].outline_color,
            Some(Outcome::Matched.color())
        );
        assert_eq!(decided.texts[0].text, "H2001 -> R1007 0.93");
        assert_eq!(
            decided.points[1].outline_color,
            Some(Outcome::Undecided.color())
        );
        let robot = camera(vec![square(1007, 0, 10), square(1008, 9, 9)]);
        let drawn = annotations(&robot, Side::Robot, &latest, "s", time());
        assert_eq!(
            drawn.points[0].outline_color,
            Some(Outcome::Matched.color())
        );
        assert_eq!(drawn.texts[0].text, "R1007");
        assert_eq!(
            drawn.points[1].outline_color,
            Some(Outcome::Undecided.color())
        );
        assert_ne!(
            annotation_key(&c, Side::Human, &latest),
            annotation_key(&c, Side::Human, &Latest::default())
        );
    }

    #[test]
    fn an_object_without_outline_draws_nothing_of_it_but_keeps_its_place() {
        let c = camera(vec![ImageObject {
            track_id: 1,
            polygons: Vec::new(),
        }]);
        let a = annotations(&c, Side::Robot, &Latest::default(), "s", time());
        assert_eq!(a.points.len(), 1);
        assert!(a.points[0].points.is_empty());
        assert!(a.texts.is_empty());
    }
}
