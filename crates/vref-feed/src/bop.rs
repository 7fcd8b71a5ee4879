//! BOP scenes as live feeds: each scene's robot image and headset image,
//! measured by the perception front end at start-up, shown in turn for
//! `hold_s` seconds each (like a dataset), and the person pointing from
//! the headset camera at one object both views measured, another one
//! every half scene. Everything is a function of the time since the
//! epoch, so the two feeds (and `vref demo`, which checks the answers)
//! agree without talking.

use std::path::Path;

use vref_import::{BopDataset, BopImport, BopOptions, BopSceneDir, MeasuredView, datasets_in};
use vref_perception::PerceptionSettings;
use vref_scene::{Limits, ScenePair, Side};

use crate::dataset::DatasetSource;
use crate::ticks::Ticker;
use crate::{Due, Publication, Ray, SetupError, Target};

/// Track ids of scene `k` are offset by `k` times this, so that no id
/// names two objects (the front end numbers each scene's objects from the
/// same bases).
const SCENE_ID_STRIDE: u64 = 100_000;
/// Pointing targets per scene.
const SLOTS_PER_SCENE: f64 = 2.0;
/// Cone half-angle of the rays, radians (as `vref query --ray`'s default).
const CONE_HALF_ANGLE: f64 = 0.1;

/// The measured scenes and their timing.
#[derive(Debug, Clone)]
pub struct BopWorld {
    pairs: Vec<ScenePair>,
    sources: Vec<BopSceneSource>,
    hold_s: f64,
}

/// Where one scene's images are and the track id the feeds publish each
/// instance under: what a viewer needs to show the images of the scene
/// being fed.
#[derive(Debug, Clone, PartialEq)]
pub struct BopSceneSource {
    /// Dataset folder and scene id, `table/000003`.
    pub name: String,
    pub scene: BopSceneDir,
    pub robot: BopImageSource,
    pub human: BopImageSource,
}

/// One view's image of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct BopImageSource {
    /// The image's number in the scene folder.
    pub image: u32,
    /// Per instance, in `scene_gt.json`'s order (the masks' order): the
    /// track id its object is published under, `None` where the front end
    /// skipped the mask.
    pub track_ids: Vec<Option<u64>>,
}

impl BopImageSource {
    fn of(image: u32, view: &MeasuredView, offset: u64) -> Self {
        Self {
            image,
            track_ids: (0..view.track_ids.len())
                .map(|k| view.measured_id(k).map(|id| id + offset))
                .collect(),
        }
    }
}

/// Where the person points during one slot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BopGesture {
    pub slot: i64,
    /// Index of the scene shown.
    pub scene: usize,
    pub human_id: u64,
    /// The robot object it is (the ground truth).
    pub robot_id: u64,
    /// From the headset camera (its frame's origin) towards the object.
    pub origin: [f64; 3],
    pub direction: [f64; 3],
    pub cone_half_angle: f64,
    /// Seconds since the epoch when the slot began.
    pub since_s: f64,
}

impl BopWorld {
    /// Every scene of the BOP dataset(s) at `dir` (a dataset folder or a
    /// folder of them), images 0 (robot) and 1 (headset) of split `test`.
    /// Scenes that cannot be read are left out with a warning. With
    /// `world_up` (which way is up in the datasets' world frame) each view
    /// carries its camera's up vector, from the camera's pose.
    pub fn load(
        dir: &Path,
        world_up: Option<[f64; 3]>,
        perception: PerceptionSettings,
        limits: Limits,
        hold_s: f64,
    ) -> Result<Self, SetupError> {
        let bop = |source| SetupError::Bop {
            path: dir.to_owned(),
            source,
        };
        let options = BopOptions {
            robot_image: 0,
            human_image: 1,
            perception,
            world_up,
        };
        let mut pairs = Vec::new();
        let mut sources = Vec::new();
        for folder in datasets_in(dir, "test").map_err(bop)? {
            let dataset = BopDataset::open(&folder, "test").map_err(bop)?;
            let import = BopImport::run(&dataset, &options);
            for (scene, error) in &import.failed {
                tracing::warn!(
                    "BOP scene {scene} left out: {}",
                    vref_logging::with_causes(error)
                );
            }
            for scene in &import.scenes {
                if let Some(warning) = scene.missing_up().filter(|_| world_up.is_some()) {
                    tracing::warn!("BOP {warning}");
                }
                let Some(scene_dir) = dataset
                    .scenes()
                    .iter()
                    .find(|d| dataset.scene_name(d) == scene.name)
                else {
                    continue;
                };
                let offset = SCENE_ID_STRIDE * pairs.len() as u64;
                let pair = scene.pair(&limits).map_err(bop)?;
                pairs.push(offset_ids(&pair, offset, &limits).map_err(bop)?);
                sources.push(BopSceneSource {
                    name: scene.name.clone(),
                    scene: scene_dir.clone(),
                    robot: BopImageSource::of(options.robot_image, &scene.robot, offset),
                    human: BopImageSource::of(options.human_image, &scene.human, offset),
                });
            }
        }
        if pairs.is_empty() {
            return Err(SetupError::EmptyBop {
                path: dir.to_owned(),
            });
        }
        Ok(Self {
            pairs,
            sources,
            hold_s,
        })
    }

    pub fn pairs(&self) -> &[ScenePair] {
        &self.pairs
    }

    /// Where each scene's images are, in the order of [`Self::pairs`].
    pub fn sources(&self) -> &[BopSceneSource] {
        &self.sources
    }

    /// Seconds each target is pointed at.
    pub fn slot_s(&self) -> f64 {
        self.hold_s / SLOTS_PER_SCENE
    }

    /// The scene shown `t` seconds after the epoch (as the dataset source
    /// chooses it).
    pub fn scene_at(&self, t: f64) -> usize {
        let count = self.pairs.len() as i64;
        let slot = (t / self.hold_s).floor() as i64;
        usize::try_from(slot.rem_euclid(count.max(1))).unwrap_or(0)
    }

    /// Where the person points at `t`: one of the scene's true pairs,
    /// drawn per slot; `None` in a scene without any.
    pub fn gesture(&self, t: f64) -> Option<BopGesture> {
        let slot_s = self.slot_s();
        let slot = (t / slot_s).floor() as i64;
        let since_s = slot as f64 * slot_s;
        // The scene of the slot's middle: slots never straddle scenes.
        let scene = self.scene_at(since_s + 0.5 * slot_s);
        let pair = &self.pairs[scene];
        if pair.ground_truth.is_empty() {
            return None;
        }
        let pick = splitmix(slot as u64) % pair.ground_truth.len() as u64;
        let (human_id, robot_id) = pair.ground_truth[usize::try_from(pick).unwrap_or(0)];
        let object = &pair.human.objects()[pair.human.index_of(human_id)?];
        let direction = object.position.coords.normalize();
        Some(BopGesture {
            slot,
            scene,
            human_id,
            robot_id,
            origin: [0.0; 3],
            direction: direction.into(),
            cone_half_angle: CONE_HALF_ANGLE,
            since_s,
        })
    }
}

/// `pair` with every track id raised by `offset`.
fn offset_ids(
    pair: &ScenePair,
    offset: u64,
    limits: &Limits,
) -> Result<ScenePair, vref_import::ImportError> {
    let invalid = |side| {
        let name = pair.name.clone();
        move |source| vref_import::ImportError::Invalid {
            name,
            source: vref_scene::PairError::Graph { side, source },
        }
    };
    let robot = pair
        .robot
        .with_ids_raised(offset, limits)
        .map_err(invalid(Side::Robot))?;
    let human = pair
        .human
        .with_ids_raised(offset, limits)
        .map_err(invalid(Side::Human))?;
    let truth = pair
        .ground_truth
        .iter()
        .map(|&(h, r)| (h + offset, r + offset))
        .collect();
    ScenePair::new(pair.name.clone(), robot, human, truth).map_err(|source| {
        vref_import::ImportError::Invalid {
            name: pair.name.clone(),
            source,
        }
    })
}

/// A well-mixed hash of a slot number (SplitMix64's finaliser).
fn splitmix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The feed source: one view's snapshots, and for the gesture feed the
/// rays.
#[derive(Debug)]
pub(crate) struct BopSource {
    snapshots: DatasetSource,
    world: BopWorld,
    gestures: Option<Ticker>,
}

impl BopSource {
    pub(crate) fn new(
        world: BopWorld,
        side: Side,
        epoch_ns: u64,
        rate_hz: f64,
        gesture_rate_hz: Option<f64>,
    ) -> Result<Self, SetupError> {
        let snapshots =
            DatasetSource::from_pairs("BOP", world.pairs(), side, world.hold_s, epoch_ns, rate_hz)?;
        Ok(Self {
            snapshots,
            world,
            gestures: gesture_rate_hz.map(|rate| Ticker::new(epoch_ns, rate)),
        })
    }

    pub(crate) fn scenes(&self) -> usize {
        self.world.pairs().len()
    }

    pub(crate) fn next(&mut self, now_ns: u64) -> Due<'_> {
        if let Some(gestures) = &mut self.gestures {
            gestures.start(now_ns);
            let tick = gestures.peek(now_ns);
            if tick.at_ns <= self.snapshots.peek_at(now_ns) {
                gestures.take(tick);
                if let Some(g) = self.world.gesture(tick.t) {
                    return Due {
                        at_ns: tick.at_ns,
                        publication: Publication::Gesture {
                            ray: Ray {
                                origin: g.origin.map(|v| v as f32),
                                direction: g.direction.map(|v| v as f32),
                                cone_half_angle: g.cone_half_angle as f32,
                                confidence: 1.0,
                            },
                            target: Some(Target {
                                slot: g.slot,
                                human_id: g.human_id,
                                robot_id: g.robot_id,
                            }),
                        },
                    };
                }
            }
        }
        self.snapshots.next(now_ns)
    }
}
