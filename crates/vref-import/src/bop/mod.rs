//! BOP datasets (RGB-D images, instance masks, ground-truth poses) to
//! two-view scene pairs: image `robot_image` of each scene is the robot's
//! view, `human_image` the headset's, objects come from the perception
//! front end, and the instance index is the ground truth of which object
//! is which.

mod layout;

use image::GrayImage;
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use vref_perception::{
    Detection, Frame, FrontEnd, LabelImage, Mask, NoSupport, PerceptionSettings, RgbdFrame,
    Segmentation, SegmentationSettings, Segmenter, Skipped, label_masks,
};
use vref_scene::{Limits, SceneGraph, SceneObject, ScenePair, Side};

pub use layout::{BopDataset, BopSceneDir, BopView, datasets_in};

use crate::ImportError;

/// Which images make the two views, and the front end's settings.
#[derive(Debug, Clone, PartialEq)]
pub struct BopOptions {
    pub robot_image: u32,
    pub human_image: u32,
    pub perception: PerceptionSettings,
    /// The up direction (against gravity) in the dataset's world frame:
    /// with it, each view carries its camera's up vector from `cam_R_w2c`.
    /// BOP does not say which way its worlds stand, so it is the user's to
    /// give (the rendered scenes of ../shared/data/bop: `[0, 0, 1]`).
    pub world_up: Option<[f64; 3]>,
}

/// Track ids of robot objects start here, of human objects at
/// [`HUMAN_IDS`]: the two never coincide, and neither tells the instance.
pub const ROBOT_IDS: u64 = 1000;
pub const HUMAN_IDS: u64 = 2000;
/// With the segmenter's masks, an instance that no segment is keeps an id
/// this far above its view's base (no view has 500 segments).
const UNMATCHED_OFFSET: u64 = 500;

/// The instance whose mask `segment` (of `area` pixels) overlaps with the
/// largest intersection over union, if that is at least [`MIN_TRUTH_IOU`].
fn best_instance(segment: &GrayImage, area: u64, masks: &[GrayImage]) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (k, mask) in masks.iter().enumerate() {
        if mask.dimensions() != segment.dimensions() {
            continue;
        }
        let (mut both, mut truth) = (0u64, 0u64);
        for (s, m) in segment.as_raw().iter().zip(mask.as_raw()) {
            let in_mask = *m != 0;
            truth += u64::from(in_mask);
            both += u64::from(in_mask && *s != 0);
        }
        let union = area + truth - both;
        let iou = if union == 0 {
            0.0
        } else {
            both as f64 / union as f64
        };
        if iou >= MIN_TRUTH_IOU && best.is_none_or(|(_, b)| iou > b) {
            best = Some((k, iou));
        }
    }
    best.map(|(k, _)| k)
}

/// One view as the front end measured it.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredView {
    /// In the view's (shuffled) object order.
    pub detections: Vec<Detection>,
    /// The ground-truth instance of each detection; `None` for a segment
    /// that overlaps no instance enough (see [`MIN_TRUTH_IOU`]).
    pub instances: Vec<Option<usize>>,
    /// Track id of every instance, measured or not.
    pub track_ids: Vec<u64>,
    pub skipped: Skipped,
    /// Which way is up in the camera frame, where known.
    pub up: Option<[f64; 3]>,
    /// Why the segmenter found no objects, when it measured the view and
    /// found no supporting plane.
    pub no_support: Option<NoSupport>,
}

/// Least intersection over union with an instance's visible mask for a
/// segment to be that instance: at 0.5 or more no other segment can claim
/// the same instance, so the ground truth stays one-to-one.
pub const MIN_TRUTH_IOU: f64 = 0.5;

impl MeasuredView {
    /// Measures `view` with `front_end`; instance `k` is reported under
    /// `track_ids[k]`, and objects are listed in the order of their ids.
    pub fn measure(
        view: &BopView,
        track_ids: Vec<u64>,
        front_end: &mut FrontEnd,
    ) -> Result<Self, vref_perception::FrameError> {
        let mut order: Vec<usize> = (0..view.masks.len()).collect();
        order.sort_by_key(|&k| track_ids[k]);
        let masks: Vec<Mask<'_>> = order
            .iter()
            .map(|&k| Mask {
                id: track_ids[k],
                pixels: &view.masks[k],
            })
            .collect();
        let frame = Frame {
            colour: &view.colour,
            depth: &view.depth,
            intrinsics: view.intrinsics,
            masks: &masks,
        };
        let mut detections = Vec::with_capacity(masks.len());
        let skipped = front_end.process(&frame, &mut detections)?;
        let instances = detections
            .iter()
            .map(|d| track_ids.iter().position(|&id| id == d.id))
            .collect();
        Ok(Self {
            detections,
            instances,
            track_ids,
            skipped,
            up: None,
            no_support: None,
        })
    }

    /// Measures `view` on the segmenter's masks instead of the dataset's:
    /// segment `j` (in label order) is reported under `segment_ids[j]`, and
    /// its instance is the one whose visible mask it overlaps with an
    /// intersection over union of at least [`MIN_TRUTH_IOU`]. An instance
    /// no segment is reports the id `unmatched_base + k`, which no
    /// detection has. `origin` (the scene folder and image number) names
    /// the view in errors. `up` (the camera's, from the world's) is checked
    /// against the plane; without it the plane's normal is the view's up.
    pub fn measure_segmented(
        view: &BopView,
        origin: (&std::path::Path, u32),
        up: Option<[f64; 3]>,
        segmenter: &mut Segmenter,
        ids: impl Fn(usize) -> Vec<u64>,
        unmatched_base: u64,
        front_end: &mut FrontEnd,
    ) -> Result<Self, ImportError> {
        let (path, image) = (origin.0.to_owned(), origin.1);
        let mut labels = LabelImage::new(1, 1);
        let frame = RgbdFrame {
            colour: &view.colour,
            depth: &view.depth,
            intrinsics: view.intrinsics,
            up,
        };
        let segmentation =
            segmenter
                .segment(&frame, &mut labels)
                .map_err(|source| ImportError::Segment {
                    path: path.clone(),
                    image,
                    source,
                })?;
        // Without the world's up, the plane the objects stand on says
        // which way is up, as it does for the feeds and `vref match`.
        let (no_support, up) = match segmentation {
            Segmentation::Objects { plane, .. } => (None, up.or(Some(plane.normal))),
            Segmentation::NoSupport(reason) => (Some(reason), up),
        };
        let segments = label_masks(&labels);
        let segment_ids = ids(segments.len());
        let truth: Vec<Option<usize>> = segments
            .iter()
            .map(|s| best_instance(&s.pixels, s.area, &view.masks))
            .collect();
        let mut order: Vec<usize> = (0..segments.len()).collect();
        order.sort_by_key(|&j| segment_ids[j]);
        let masks: Vec<Mask<'_>> = order
            .iter()
            .map(|&j| Mask {
                id: segment_ids[j],
                pixels: &segments[j].pixels,
            })
            .collect();
        let frame = Frame {
            colour: &view.colour,
            depth: &view.depth,
            intrinsics: view.intrinsics,
            masks: &masks,
        };
        let mut detections = Vec::with_capacity(masks.len());
        let skipped = front_end
            .process(&frame, &mut detections)
            .map_err(|source| ImportError::Frame {
                path,
                image,
                source,
            })?;
        let instances: Vec<Option<usize>> = detections
            .iter()
            .map(|d| {
                segment_ids
                    .iter()
                    .position(|&id| id == d.id)
                    .and_then(|j| truth[j])
            })
            .collect();
        let track_ids = (0..view.masks.len())
            .map(|k| {
                instances
                    .iter()
                    .position(|&i| i == Some(k))
                    .map_or(unmatched_base + k as u64, |p| detections[p].id)
            })
            .collect();
        Ok(Self {
            detections,
            instances,
            track_ids,
            skipped,
            up,
            no_support,
        })
    }

    /// The track id of the detection of instance `k`, if it was measured.
    pub fn measured_id(&self, k: usize) -> Option<u64> {
        self.instances
            .iter()
            .position(|&i| i == Some(k))
            .map(|p| self.detections[p].id)
    }

    /// The view as a scene graph, with stated position errors.
    pub fn graph(&self, limits: &Limits) -> Result<SceneGraph, vref_scene::GraphError> {
        let objects = self
            .detections
            .iter()
            .map(|d| SceneObject::new(d.id, d.position, d.feature.to_vec()).with_sigma(d.sigma))
            .collect();
        SceneGraph::new(objects, None, limits)?.with_up(self.up)
    }
}

/// One BOP scene measured in both views.
#[derive(Debug, Clone, PartialEq)]
pub struct BopScene {
    /// Dataset folder and scene id, `table/000003`.
    pub name: String,
    pub robot: MeasuredView,
    pub human: MeasuredView,
}

impl BopScene {
    /// Whether a view carries no up vector: with `world_up`, a camera
    /// without a pose (`cam_R_w2c`) and, for vref's own segments, without
    /// a supporting plane either.
    pub fn lacks_up(&self) -> bool {
        self.robot.up.is_none() || self.human.up.is_none()
    }

    /// What to warn of where the world's up was given and a view still
    /// lacks one ([`BopScene::lacks_up`]); `None` where both carry one.
    pub fn missing_up(&self) -> Option<String> {
        self.lacks_up().then(|| {
            format!(
                "scene {}: a camera has no pose (cam_R_w2c), so a view carries no up vector",
                self.name
            )
        })
    }

    /// Loads and measures both views of `scene`.
    pub fn measure(
        dataset: &BopDataset,
        scene: &BopSceneDir,
        options: &BopOptions,
    ) -> Result<Self, ImportError> {
        let mut robot_end = FrontEnd::new(options.perception.robot());
        let mut human_end = FrontEnd::new(options.perception.human());
        let view = |image: u32, base: u64, front_end: &mut FrontEnd| {
            let loaded = scene.load_view(image, options.perception.image_limit())?;
            let ids = track_ids(scene.id, image, loaded.masks.len(), base);
            let mut measured =
                MeasuredView::measure(&loaded, ids, front_end).map_err(|source| {
                    ImportError::Frame {
                        path: scene.dir.clone(),
                        image,
                        source,
                    }
                })?;
            measured.up = camera_up(&loaded, options.world_up);
            Ok::<_, ImportError>(measured)
        };
        Ok(Self {
            name: dataset.scene_name(scene),
            robot: view(options.robot_image, ROBOT_IDS, &mut robot_end)?,
            human: view(options.human_image, HUMAN_IDS, &mut human_end)?,
        })
    }

    /// Loads both views of `scene` and measures them on the segmenter's
    /// masks (see [`MeasuredView::measure_segmented`]), each view's
    /// segmenter set for its camera's depth noise
    /// ([`SegmentationSettings::for_camera`]).
    pub fn measure_segmented(
        dataset: &BopDataset,
        scene: &BopSceneDir,
        options: &BopOptions,
        segmentation: &SegmentationSettings,
    ) -> Result<Self, ImportError> {
        let mut robot_end = FrontEnd::new(options.perception.robot());
        let mut human_end = FrontEnd::new(options.perception.human());
        let mut robot_segmenter =
            Segmenter::new(segmentation.for_camera(options.perception.robot.pixel));
        let mut human_segmenter =
            Segmenter::new(segmentation.for_camera(options.perception.human.pixel));
        let view = |image: u32, base: u64, front_end: &mut FrontEnd, segmenter: &mut Segmenter| {
            let loaded = scene.load_view(image, options.perception.image_limit())?;
            let up = camera_up(&loaded, options.world_up);
            let ids = |n| track_ids(scene.id, image, n, base);
            // Past every segment's id: the ids of instances no segment is.
            let unmatched = base + UNMATCHED_OFFSET;
            MeasuredView::measure_segmented(
                &loaded,
                (&scene.dir, image),
                up,
                segmenter,
                ids,
                unmatched,
                front_end,
            )
        };
        let robot = view(
            options.robot_image,
            ROBOT_IDS,
            &mut robot_end,
            &mut robot_segmenter,
        )?;
        let human = view(
            options.human_image,
            HUMAN_IDS,
            &mut human_end,
            &mut human_segmenter,
        )?;
        Ok(Self {
            name: dataset.scene_name(scene),
            robot,
            human,
        })
    }

    /// (human id, robot id) of every instance both views measured.
    pub fn truth(&self) -> Vec<(u64, u64)> {
        let mut pairs: Vec<(u64, u64)> = self
            .human
            .instances
            .iter()
            .zip(&self.human.detections)
            .filter_map(|(&k, d)| Some((d.id, self.robot.measured_id(k?)?)))
            .collect();
        pairs.sort_unstable();
        pairs
    }

    /// The scene as a dataset's scene pair.
    pub fn pair(&self, limits: &Limits) -> Result<ScenePair, ImportError> {
        let invalid = |side| {
            let name = self.name.clone();
            move |source| ImportError::Invalid {
                name,
                source: vref_scene::PairError::Graph { side, source },
            }
        };
        let robot = self.robot.graph(limits).map_err(invalid(Side::Robot))?;
        let human = self.human.graph(limits).map_err(invalid(Side::Human))?;
        ScenePair::new(self.name.clone(), robot, human, self.truth()).map_err(|source| {
            ImportError::Invalid {
                name: self.name.clone(),
                source,
            }
        })
    }
}

/// The world's `world_up` in `view`'s camera frame, where both are known.
fn camera_up(view: &BopView, world_up: Option<[f64; 3]>) -> Option<[f64; 3]> {
    let (r, up) = (view.world_to_camera?, world_up?);
    Some(std::array::from_fn(|row| {
        (0..3).map(|k| r[3 * row + k] * up[k]).sum::<f64>()
    }))
}

/// Track ids of a view's `n` instances: `base` plus the instance's place
/// in an order shuffled per scene and image, so that an id says nothing
/// of the instance and the two views' ids differ.
pub fn track_ids(scene: u32, image: u32, n: usize, base: u64) -> Vec<u64> {
    let mut order: Vec<u64> = (0..n as u64).collect();
    let seed = (u64::from(scene) << 32) | u64::from(image);
    order.shuffle(&mut ChaCha8Rng::seed_from_u64(seed));
    order.into_iter().map(|p| base + p).collect()
}

/// The scenes of a dataset that could be measured, and why the others
/// could not.
#[derive(Debug)]
pub struct BopImport {
    pub scenes: Vec<BopScene>,
    pub failed: Vec<(String, ImportError)>,
}

impl BopImport {
    /// Every scene of `dataset`; a scene that fails is set aside with its
    /// error, and the others are measured.
    pub fn run(dataset: &BopDataset, options: &BopOptions) -> Self {
        let mut scenes = Vec::new();
        let mut failed = Vec::new();
        for scene in dataset.scenes() {
            match BopScene::measure(dataset, scene, options) {
                Ok(s) => scenes.push(s),
                Err(e) => failed.push((dataset.scene_name(scene), e)),
            }
        }
        Self { scenes, failed }
    }

    /// Every scene of `dataset` on the segmenter's masks; a scene that
    /// fails is set aside with its error, and the others are measured.
    pub fn run_segmented(
        dataset: &BopDataset,
        options: &BopOptions,
        segmentation: &SegmentationSettings,
    ) -> Self {
        let mut scenes = Vec::new();
        let mut failed = Vec::new();
        for scene in dataset.scenes() {
            match BopScene::measure_segmented(dataset, scene, options, segmentation) {
                Ok(s) => scenes.push(s),
                Err(e) => failed.push((dataset.scene_name(scene), e)),
            }
        }
        Self { scenes, failed }
    }

    /// Views where the segmenter found no supporting plane, with the
    /// scene's name and why.
    pub fn no_support(&self) -> Vec<(String, NoSupport)> {
        self.scenes
            .iter()
            .flat_map(|s| {
                [&s.robot, &s.human]
                    .into_iter()
                    .filter_map(|v| v.no_support.map(|r| (s.name.clone(), r)))
            })
            .collect()
    }

    /// Masks skipped in all scenes, both views.
    pub fn skipped(&self) -> Skipped {
        let mut total = Skipped::default();
        for view in self.scenes.iter().flat_map(|s| [&s.robot, &s.human]) {
            total.too_small += view.skipped.too_small;
            total.no_depth += view.skipped.no_depth;
            total.whole_frame += view.skipped.whole_frame;
        }
        total
    }
}

/// A mask's outline pixels (in the mask, with a 4-neighbour outside it),
/// for pictures.
pub fn outline(mask: &GrayImage) -> Vec<(u32, u32)> {
    let (w, h) = mask.dimensions();
    let inside = |u: i64, v: i64| {
        u >= 0
            && v >= 0
            && u < i64::from(w)
            && v < i64::from(h)
            && mask.get_pixel(u as u32, v as u32).0[0] != 0
    };
    let mut out = Vec::new();
    for v in 0..h {
        for u in 0..w {
            let (x, y) = (i64::from(u), i64::from(v));
            if inside(x, y)
                && !(inside(x - 1, y) && inside(x + 1, y) && inside(x, y - 1) && inside(x, y + 1))
            {
                out.push((u, v));
            }
        }
    }
    out
}
