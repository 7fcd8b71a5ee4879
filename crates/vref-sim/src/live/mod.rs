//! A workspace that changes over time, seen by the same two cameras as a
//! generated scene: objects drift and turn slowly about their home places,
//! are taken away and put back, and the headset sways with the person's
//! head.
//!
//! Everything is a pure function of the configuration, the dynamics, the
//! seed and the time `t` (seconds since an epoch the caller chooses, e.g.
//! the Unix epoch for wall-clock time): two processes that share these
//! compute the same world without talking. A camera's measurement errors
//! come from a stream keyed by its side and a frame number, so the same
//! frame number measures the same way.

use nalgebra::{Point3, Vector3};
use rand::Rng;
use vref_scene::{GraphError, Limits, SceneGraph, SceneObject, Side};

use crate::ConfigError;
use crate::appearance::Light;
use crate::camera::Camera;
use crate::config::{CameraSpec, SimConfig, invalid};
use crate::dynamics::Dynamics;
use crate::generator::distinct_ids;
use crate::measurement::measure;
use crate::motion::{Motion, Sway};
use crate::random::{Purpose, keyed};
use crate::staging::stage;
use crate::visibility::{Detection, detect};
use crate::world::{WorldObject, arrange, draw_instance, draw_objects};

mod pointing;

pub use pointing::Gesture;

/// A time-varying workspace. See the module documentation.
#[derive(Debug, Clone)]
pub struct LiveWorld {
    config: SimConfig,
    dynamics: Dynamics,
    seed: u64,
    /// Every object at its home place, in its first pose.
    homes: Vec<WorldObject>,
    motions: Vec<Motion>,
    light: Light,
    robot: Camera,
    /// The headset at rest; it sways about this pose.
    human: Camera,
    head: Sway<3>,
    robot_ids: Vec<u64>,
    human_ids: Vec<u64>,
}

/// What one camera reports at one time.
#[derive(Debug, Clone, PartialEq)]
pub struct LiveView {
    pub side: Side,
    pub t: f64,
    pub frame: u64,
    /// The camera's pose at `t`.
    pub camera: Camera,
    /// The detected objects, by track id (ascending).
    pub objects: Vec<LiveObject>,
}

/// One detected object of a [`LiveView`].
#[derive(Debug, Clone, PartialEq)]
pub struct LiveObject {
    /// Index of the world object ([`LiveWorld::object_count`]).
    pub object: usize,
    pub id: u64,
    /// Measured position in the camera frame (x right, y down, z forward).
    pub position: Point3<f64>,
    /// The sensor model's standard deviation of `position` per axis: the
    /// depth error along the line of sight (`k z^2` and the depth scale
    /// error) and the segmentation error's share of the object's size.
    pub sigma: [f64; 3],
    pub feature: Vec<f32>,
}

/// The world's objects at one time.
struct Moment {
    /// World indices of the objects present.
    present: Vec<usize>,
    objects: Vec<WorldObject>,
}

impl LiveWorld {
    /// Lays out the workspace and poses both cameras as the generator does,
    /// with room for the drift. `objects` fixes how many objects there
    /// are (classes drawn in proportion to their mean instance counts);
    /// `None` draws the count per class as the configuration says.
    pub fn new(
        config: SimConfig,
        dynamics: Dynamics,
        seed: u64,
        objects: Option<usize>,
    ) -> Result<Self, ConfigError> {
        config.validate()?;
        dynamics.validate()?;
        let capacity = Limits::default().capacity;
        if let Some(n) = objects
            && !(1..=capacity).contains(&n)
        {
            return Err(invalid(
                "objects",
                format!("{n} must lie in [1, {capacity}]"),
            ));
        }
        // Drifting objects may each come `drift_amplitude` closer to a
        // neighbour or an edge: lay out with that much more room.
        let drift = dynamics.drift_amplitude;
        let mut room = config.workspace.clone();
        room.area = room.area.map(|a| a - 2.0 * drift);
        room.min_gap += 2.0 * drift;
        let mut rng = keyed(seed, Purpose::Setup, 0, 0);
        for _ in 0..config.attempts {
            let drawn = match objects {
                Some(n) => draw_count(&config, n, &mut rng),
                None => draw_objects(&config, &mut rng),
            };
            let Some(placed) = arrange(drawn, &room, &mut rng) else {
                continue;
            };
            let Some(stage) = stage(&config, placed, &mut rng) else {
                continue;
            };
            let n = stage.objects.len();
            let robot_ids = distinct_ids(&mut rng, n);
            let human_ids = distinct_ids(&mut rng, n);
            let motions = (0..n as u64)
                .map(|k| Motion::draw(&dynamics, k, &mut rng))
                .collect();
            let head = Sway::draw(dynamics.head_sway_period_s, &mut rng);
            return Ok(Self {
                config,
                dynamics,
                seed,
                homes: stage.objects,
                motions,
                light: stage.light,
                robot: stage.robot,
                human: stage.human,
                head,
                robot_ids,
                human_ids,
            });
        }
        let what = objects.map_or_else(
            || "the configured objects".to_owned(),
            |n| format!("{n} objects"),
        );
        Err(invalid(
            if objects.is_some() {
                "objects"
            } else {
                "dynamics.drift_amplitude"
            },
            format!(
                "no layout of {what} with {drift} m of drift room in {} attempts lets both \
                 views see at least {} objects",
                config.attempts, config.min_objects_per_view
            ),
        ))
    }

    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    pub fn dynamics(&self) -> &Dynamics {
        &self.dynamics
    }

    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Objects in the world, present or away.
    pub fn object_count(&self) -> usize {
        self.homes.len()
    }

    /// Track id of world object `object` in `side`'s view, the same for the
    /// whole run; ids of the two views are unrelated.
    pub fn track_id(&self, side: Side, object: usize) -> Option<u64> {
        match side {
            Side::Robot => self.robot_ids.get(object).copied(),
            Side::Human => self.human_ids.get(object).copied(),
        }
    }

    /// World object `object` at `t`, or `None` while it is away (or if
    /// there is no such object).
    pub fn object(&self, object: usize, t: f64) -> Option<WorldObject> {
        let motion = self.motions.get(object)?;
        if motion.away(&self.dynamics, self.seed, t) {
            return None;
        }
        Some(self.pose(object, t))
    }

    /// Whether world object `object` is away at some time in `[from, to]`.
    pub fn away_during(&self, object: usize, from: f64, to: f64) -> bool {
        self.motions
            .get(object)
            .is_some_and(|m| m.away_during(&self.dynamics, self.seed, from, to))
    }

    /// `side`'s camera at `t`.
    pub fn camera(&self, side: Side, t: f64) -> Camera {
        match side {
            Side::Robot => self.robot,
            Side::Human => {
                let sway = self
                    .head
                    .at(t)
                    .map(|s| s * self.dynamics.head_sway / 3f64.sqrt());
                Camera {
                    position: self.human.position + Vector3::from(sway),
                    ..self.human
                }
            }
        }
    }

    /// What `side`'s camera reports at `t`, with the measurement errors
    /// of frame number `frame`.
    pub fn observe(&self, side: Side, t: f64, frame: u64) -> LiveView {
        let moment = self.moment(t);
        let camera = self.camera(side, t);
        let spec = self.spec(side);
        let detections = self.detect(&moment, &camera, spec);
        let mut rng = keyed(self.seed, Purpose::Frame, side as u64, frame);
        let measured = measure(
            &self.config,
            &moment.objects,
            &self.light,
            &camera,
            spec,
            &detections,
            &mut rng,
        );
        let mut objects: Vec<LiveObject> = detections
            .iter()
            .zip(measured)
            .filter_map(|(detection, m)| {
                let object = *moment.present.get(detection.object)?;
                let shape = moment.objects.get(detection.object)?.shape;
                Some(LiveObject {
                    object,
                    id: self.track_id(side, object)?,
                    sigma: sigma(spec, &m.position, shape.bounding_radius()),
                    position: m.position,
                    feature: m.feature,
                })
            })
            .collect();
        objects.sort_unstable_by_key(|o| o.id);
        LiveView {
            side,
            t,
            frame,
            camera,
            objects,
        }
    }

    /// World indices of the objects `side`'s camera detects at `t`,
    /// ascending.
    pub fn detected(&self, side: Side, t: f64) -> Vec<usize> {
        let moment = self.moment(t);
        let camera = self.camera(side, t);
        self.detect(&moment, &camera, self.spec(side))
            .iter()
            .filter_map(|d| moment.present.get(d.object).copied())
            .collect()
    }

    /// (human id, robot id) of every object both cameras detect at `t`,
    /// by human id.
    pub fn truth(&self, t: f64) -> Vec<(u64, u64)> {
        let robot = self.detected(Side::Robot, t);
        let mut pairs: Vec<(u64, u64)> = self
            .detected(Side::Human, t)
            .into_iter()
            .filter(|k| robot.binary_search(k).is_ok())
            .filter_map(|k| {
                Some((
                    self.track_id(Side::Human, k)?,
                    self.track_id(Side::Robot, k)?,
                ))
            })
            .collect();
        pairs.sort_unstable();
        pairs
    }

    /// Object `object` where its motion has it at `t`, present or not.
    fn pose(&self, object: usize, t: f64) -> WorldObject {
        let home = &self.homes[object];
        let motion = &self.motions[object];
        WorldObject {
            centre: home.centre + motion.drift(&self.dynamics, t),
            yaw: motion.yaw(&self.dynamics, self.seed, home.yaw, t),
            ..home.clone()
        }
    }

    fn moment(&self, t: f64) -> Moment {
        let present: Vec<usize> = (0..self.homes.len())
            .filter(|&k| !self.motions[k].away(&self.dynamics, self.seed, t))
            .collect();
        let objects = present.iter().map(|&k| self.pose(k, t)).collect();
        Moment { present, objects }
    }

    fn detect(&self, moment: &Moment, camera: &Camera, spec: &CameraSpec) -> Vec<Detection> {
        let surfaces: Vec<_> = moment.objects.iter().map(WorldObject::surface).collect();
        detect(camera, &moment.objects, &surfaces, spec)
    }

    fn spec(&self, side: Side) -> &CameraSpec {
        match side {
            Side::Robot => &self.config.robot,
            Side::Human => &self.config.human,
        }
    }
}

impl LiveView {
    /// The view as a scene graph.
    pub fn graph(&self, limits: &Limits) -> Result<SceneGraph, GraphError> {
        let objects = self
            .objects
            .iter()
            .map(|o| {
                SceneObject::new(o.id, o.position.coords.into(), o.feature.clone())
                    .with_sigma(o.sigma)
            })
            .collect();
        SceneGraph::new(objects, None, limits)
    }
}

/// `n` objects of classes drawn in proportion to their mean instance
/// counts.
fn draw_count<R: Rng>(config: &SimConfig, n: usize, rng: &mut R) -> Vec<WorldObject> {
    // Twice the mean instance count; validation guarantees a class with
    // at least one instance, so the total is positive.
    let weights: Vec<usize> = config
        .classes
        .iter()
        .map(|c| c.instances[0] + c.instances[1])
        .collect();
    let total: usize = weights.iter().sum();
    (0..n)
        .map(|_| {
            let mut pick = rng.random_range(0..total.max(1));
            let class = weights
                .iter()
                .position(|&w| {
                    if pick < w {
                        true
                    } else {
                        pick -= w;
                        false
                    }
                })
                .unwrap_or(0);
            draw_instance(config, class, rng)
        })
        .collect()
}

/// Per-axis standard deviation of a position measured at `p` (camera
/// frame) of an object of bounding radius `radius`.
fn sigma(spec: &CameraSpec, p: &Point3<f64>, radius: f64) -> [f64; 3] {
    let noise = &spec.noise;
    // The depth error scales the whole position vector: each axis errs in
    // proportion to its own coordinate.
    let along = (noise.depth * p.z).hypot(noise.depth_scale);
    let across = noise.segmentation * radius;
    [p.x, p.y, p.z].map(|c| (c.abs() * along).hypot(across))
}
