//! Scene pairs from a configuration and a seed.

use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vref_scene::{Limits, SceneGraph, SceneObject, ScenePair, Side};

use crate::appearance::Light;
use crate::camera::Camera;
use crate::config::{CameraSpec, SimConfig};
use crate::measurement::measure;
use crate::staging::{Stage, stage};
use crate::visibility::Detection;
use crate::world::{WorldObject, place_objects};
use crate::{ConfigError, SceneError};

/// Track ids are drawn from `1..=MAX_TRACK_ID`, independently per view.
const MAX_TRACK_ID: u64 = 999_999;

/// Generates scene pairs. Scene `index` depends only on the configuration,
/// the seed and `index` (each scene has its own random stream), so any
/// prefix of a longer run is the shorter run.
#[derive(Debug, Clone)]
pub struct Generator {
    config: SimConfig,
    seed: u64,
    name: String,
    /// Whether each view carries its camera's up vector, and the standard
    /// deviation of its tilt error (radians).
    up_error: Option<f64>,
}

/// One generated scene: the pair as a dataset holds it, and the world
/// behind it.
#[derive(Debug, Clone)]
pub struct GeneratedScene {
    pub pair: ScenePair,
    /// Every object in the workspace, seen or not.
    pub objects: Vec<WorldObject>,
    pub robot: View,
    pub human: View,
}

/// What one camera of a scene saw.
#[derive(Debug, Clone)]
pub struct View {
    pub camera: Camera,
    /// The detected objects, by world index (ascending).
    pub sightings: Vec<Sighting>,
}

/// One world object in one view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sighting {
    /// Index into [`GeneratedScene::objects`].
    pub object: usize,
    /// Its track id in this view's graph.
    pub id: u64,
    /// Share of its camera-facing surface in the image and unoccluded.
    pub visible_fraction: f64,
    /// Pixels it covers.
    pub pixels: f64,
}

impl Generator {
    /// Scenes named `{name}-{seed}-{index}`; the name defaults to `sim`.
    pub fn new(config: SimConfig, seed: u64) -> Result<Self, ConfigError> {
        config.validate()?;
        Ok(Self {
            config,
            seed,
            name: "sim".to_owned(),
            up_error: None,
        })
    }

    /// Each view carries its camera's up vector (the world's vertical in
    /// the camera frame), tilted by an error of `error_deg` degrees
    /// (standard deviation, in a random direction), as a headset's or a
    /// robot's own estimate of gravity would be. The tilts are drawn from
    /// a stream of their own, so every scene is otherwise the same as
    /// without them. Refused unless finite and non-negative.
    pub fn with_up_vectors(mut self, error_deg: f64) -> Result<Self, ConfigError> {
        if !(error_deg.is_finite() && error_deg >= 0.0) {
            return Err(ConfigError::Invalid {
                field: "up vector error".to_owned(),
                message: format!("{error_deg} degrees: must be finite and non-negative"),
            });
        }
        self.up_error = Some(error_deg.to_radians());
        Ok(self)
    }

    pub fn named(mut self, name: &str) -> Self {
        self.name = name.to_owned();
        self
    }

    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    /// Scenes `0..count`, in order.
    pub fn scenes(&self, count: u64) -> impl Iterator<Item = Result<GeneratedScene, SceneError>> {
        (0..count).map(|index| self.scene(index))
    }

    /// Scene number `index`.
    pub fn scene(&self, index: u64) -> Result<GeneratedScene, SceneError> {
        let config = &self.config;
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        rng.set_stream(index);
        for _ in 0..config.attempts {
            let Some(objects) = place_objects(config, &mut rng) else {
                continue;
            };
            if let Some(stage) = stage(config, objects, &mut rng) {
                return self.assemble(index, stage, &mut rng);
            }
        }
        Err(SceneError::NoUsableView {
            index,
            attempts: config.attempts,
            min: config.min_objects_per_view,
        })
    }

    fn assemble(
        &self,
        index: u64,
        stage: Stage,
        rng: &mut ChaCha8Rng,
    ) -> Result<GeneratedScene, SceneError> {
        let invalid = |side| {
            move |source| SceneError::Invalid {
                index,
                source: ScenePair::graph_error(side)(source),
            }
        };
        let Stage {
            objects,
            light,
            robot,
            human,
            robot_detections,
            human_detections,
        } = stage;
        let (robot_graph, robot) = self.measure(
            &objects,
            &light,
            robot,
            &self.config.robot,
            &robot_detections,
            rng,
        );
        let robot_graph = robot_graph.map_err(invalid(Side::Robot))?;
        let (human_graph, human) = self.measure(
            &objects,
            &light,
            human,
            &self.config.human,
            &human_detections,
            rng,
        );
        let human_graph = human_graph.map_err(invalid(Side::Human))?;
        let (robot_graph, human_graph) = match self.up_error {
            Some(error) => {
                let mut tilts = ChaCha8Rng::seed_from_u64(self.seed ^ UP_STREAM);
                tilts.set_stream(index);
                let up = |camera: &Camera, tilts: &mut ChaCha8Rng| {
                    let up = tilted(&camera.direction_to_camera(&Vector3::z()), error, tilts);
                    Some(up.into())
                };
                (
                    robot_graph
                        .with_up(up(&robot.camera, &mut tilts))
                        .map_err(invalid(Side::Robot))?,
                    human_graph
                        .with_up(up(&human.camera, &mut tilts))
                        .map_err(invalid(Side::Human))?,
                )
            }
            None => (robot_graph, human_graph),
        };

        let mut ground_truth: Vec<(u64, u64)> = human
            .sightings
            .iter()
            .filter_map(|h| robot.id_of(h.object).map(|r| (h.id, r)))
            .collect();
        ground_truth.sort_unstable();
        let name = format!("{}-{}-{}", self.name, self.seed, index);
        let pair = ScenePair::new(name, robot_graph, human_graph, ground_truth)
            .map_err(|source| SceneError::Invalid { index, source })?;
        Ok(GeneratedScene {
            pair,
            objects,
            robot,
            human,
        })
    }

    /// The graph one camera reports: per detection a random track id, the
    /// measured centroid and the feature, listed by id so that neither ids
    /// nor order tell which object is which.
    fn measure(
        &self,
        objects: &[WorldObject],
        light: &Light,
        camera: Camera,
        spec: &CameraSpec,
        detections: &[Detection],
        rng: &mut ChaCha8Rng,
    ) -> (Result<SceneGraph, vref_scene::GraphError>, View) {
        let ids = distinct_ids(rng, detections.len());
        let measured = measure(&self.config, objects, light, &camera, spec, detections, rng);
        let mut graph_objects = Vec::with_capacity(detections.len());
        let mut sightings = Vec::with_capacity(detections.len());
        for ((detection, &id), m) in detections.iter().zip(&ids).zip(measured) {
            graph_objects.push(SceneObject::new(id, m.position.coords.into(), m.feature));
            sightings.push(Sighting {
                object: detection.object,
                id,
                visible_fraction: detection.visible_fraction,
                pixels: detection.pixels,
            });
        }
        graph_objects.sort_unstable_by_key(|o| o.id);
        let graph = SceneGraph::new(graph_objects, None, &Limits::default());
        (graph, View { camera, sightings })
    }
}

/// Seeds the up vectors' tilts apart from everything else a scene draws.
const UP_STREAM: u64 = 0x7570_7570_7570_7570;

/// Unit vector `up` tilted by an angle of standard deviation `sigma`
/// (radians) about a random axis across it.
fn tilted<R: Rng>(up: &Vector3<f64>, sigma: f64, rng: &mut R) -> Vector3<f64> {
    let angle = crate::random::normal(rng, sigma);
    let heading = crate::random::uniform(rng, [0.0, std::f64::consts::TAU]);
    let across = if up.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let a = up.cross(&across).normalize();
    let b = up.cross(&a);
    let axis = nalgebra::Unit::new_normalize(a * heading.cos() + b * heading.sin());
    nalgebra::Rotation3::from_axis_angle(&axis, angle) * up
}

/// `count` distinct track ids.
pub(crate) fn distinct_ids<R: Rng>(rng: &mut R, count: usize) -> Vec<u64> {
    let mut ids: Vec<u64> = Vec::with_capacity(count);
    while ids.len() < count {
        let id = rng.random_range(1..=MAX_TRACK_ID);
        if !ids.contains(&id) {
            ids.push(id);
        }
    }
    ids
}

impl GeneratedScene {
    pub fn view(&self, side: Side) -> &View {
        match side {
            Side::Robot => &self.robot,
            Side::Human => &self.human,
        }
    }

    /// World indices of the objects both cameras detect, ascending.
    pub fn seen_by_both(&self) -> Vec<usize> {
        self.human
            .objects()
            .into_iter()
            .filter(|&k| self.robot.id_of(k).is_some())
            .collect()
    }
}

impl View {
    /// World indices of the detected objects, ascending.
    pub fn objects(&self) -> Vec<usize> {
        self.sightings.iter().map(|s| s.object).collect()
    }

    /// The track id world object `object` has in this view, if detected.
    pub fn id_of(&self, object: usize) -> Option<u64> {
        self.sightings
            .iter()
            .find(|s| s.object == object)
            .map(|s| s.id)
    }
}
