//! The scenes `vref bench solver` times and `vref scenes --preset rigid`
//! writes: exactly `n` objects, every one seen by both views, the robot's
//! a rigid motion of the human's plus noise. Unlike [`Generator`]'s scenes
//! nothing is occluded or missed, so a solve's cost depends on the size
//! alone.
//!
//! The draws come from a SplitMix64 stream in a fixed order, not from the
//! generator's ChaCha8 streams: published timings and the tests that pin
//! them were measured on exactly these scenes, so every number must stay
//! the same to the bit.
//!
//! [`Generator`]: crate::Generator

use nalgebra::{Matrix3, Point3, Vector3};
use rand::Rng;
use vref_match::RigidMotion;
use vref_scene::{GraphError, Limits, SceneGraph, SceneObject, ScenePair};

use crate::error::RigidSceneError;
use crate::random::{SplitMix, standard_normal};

/// Extent of the synthetic workspace box, metres (a table top).
const BOX: [f64; 3] = [0.6, 0.4, 0.2];
/// Appearance feature dimension (as the moi preset's histograms).
const FEATURE_DIM: usize = 48;
/// Standard deviation of the robot's feature noise, per component.
const FEATURE_NOISE: f64 = 0.05;
/// How far the moved object of [`RigidScene::moved`] travels, metres.
const MOVE_STEP: f64 = 0.05;

/// One workspace of exactly `n` objects seen by both views: the human view
/// holds box positions, the robot view a rigid motion of them plus noise,
/// in a shuffled order. Features are random 48-d vectors, perturbed in the
/// robot view, so that appearance is informative but not decisive.
#[derive(Debug, Clone)]
pub struct RigidScene {
    pub human: SceneGraph,
    pub robot: SceneGraph,
    positions: Vec<[f64; 3]>,
    features: Vec<Vec<f32>>,
    /// Robot object `r` is human object `order[r]`.
    order: Vec<usize>,
    /// The motion taking human positions to robot positions (before
    /// noise).
    motion: RigidMotion,
}

impl RigidScene {
    /// Standard deviation of the robot's position noise, metres, unless
    /// stated otherwise ([`RigidScene::with_noise`]).
    pub const POSITION_NOISE: f64 = 0.002;

    /// The same `(objects, seed)` always gives the same scene.
    pub fn new(objects: usize, seed: u64) -> Result<Self, RigidSceneError> {
        Self::with_noise(objects, seed, Self::POSITION_NOISE)
    }

    /// [`RigidScene::new`] with the robot's positions off by `noise`
    /// (standard deviation per axis, metres) instead of
    /// [`RigidScene::POSITION_NOISE`]; the same draws otherwise.
    pub fn with_noise(objects: usize, seed: u64, noise: f64) -> Result<Self, RigidSceneError> {
        if objects < 2 {
            return Err(RigidSceneError::TooFewObjects(objects));
        }
        if !(noise.is_finite() && noise >= 0.0) {
            return Err(RigidSceneError::BadNoise(noise));
        }
        let mut rng = SplitMix::new(seed ^ (objects as u64).rotate_left(32));
        let positions: Vec<[f64; 3]> = (0..objects)
            .map(|_| BOX.map(|extent| extent * rng.random::<f64>()))
            .collect();
        let features: Vec<Vec<f32>> = (0..objects)
            .map(|_| {
                (0..FEATURE_DIM)
                    .map(|_| rng.random::<f64>() as f32)
                    .collect()
            })
            .collect();
        let human = graph(&positions, &features)?;
        let motion = random_motion(&mut rng);
        let mut order: Vec<usize> = (0..objects).collect();
        for k in (1..objects).rev() {
            order.swap(k, below(&mut rng, k + 1));
        }
        let robot_positions: Vec<[f64; 3]> = order
            .iter()
            .map(|&k| {
                let moved = motion.apply(&Point3::from(positions[k]));
                <[f64; 3]>::from(moved.coords).map(|c| c + noise * standard_normal(&mut rng))
            })
            .collect();
        let robot_features: Vec<Vec<f32>> = order
            .iter()
            .map(|&k| {
                features[k]
                    .iter()
                    .map(|&f| {
                        (f64::from(f) + FEATURE_NOISE * standard_normal(&mut rng)).max(0.0) as f32
                    })
                    .collect()
            })
            .collect();
        let robot = graph(&robot_positions, &robot_features)?;
        Ok(Self {
            human,
            robot,
            positions,
            features,
            order,
            motion,
        })
    }

    /// The scene with both views' up vectors: the human view's z, and
    /// where the motion turns it in the robot's.
    pub fn upright(self) -> Result<Self, RigidSceneError> {
        let up = self.motion.rotation.column(2);
        let up = [up[0], up[1], up[2]];
        Ok(Self {
            human: self.human.clone().with_up(Some([0.0, 0.0, 1.0]))?,
            robot: self.robot.clone().with_up(Some(up))?,
            ..self
        })
    }

    /// The scene as a dataset scene pair, with its ground truth (every
    /// object is seen by both views; ids are indices in each view).
    pub fn pair(&self, name: String) -> Result<ScenePair, RigidSceneError> {
        let truth = self
            .order
            .iter()
            .enumerate()
            .map(|(r, &h)| (h as u64, r as u64))
            .collect();
        Ok(ScenePair::new(
            name,
            self.robot.clone(),
            self.human.clone(),
            truth,
        )?)
    }

    /// The scene after human object `index % n` moved 5 cm along a
    /// direction drawn from `seed`; the robot view is unchanged, as if the
    /// headset saw the move first.
    pub fn moved(&self, index: usize, seed: u64) -> Result<Self, RigidSceneError> {
        let mut rng = SplitMix::new(seed);
        let mut positions = self.positions.clone();
        let k = index % positions.len();
        let direction = [(); 3].map(|()| standard_normal(&mut rng));
        let norm = direction
            .iter()
            .map(|d| d * d)
            .sum::<f64>()
            .sqrt()
            .max(1e-12);
        for (p, d) in positions[k].iter_mut().zip(direction) {
            *p += MOVE_STEP * d / norm;
        }
        Ok(Self {
            human: graph(&positions, &self.features)?.with_up(self.human.up().map(Into::into))?,
            robot: self.robot.clone(),
            positions,
            features: self.features.clone(),
            order: self.order.clone(),
            motion: self.motion,
        })
    }
}

/// A rotation from a random unit quaternion and a translation about a
/// metre in front. The matrix is written out from the quaternion rather
/// than taken from nalgebra's `UnitQuaternion`, which rounds its diagonal
/// differently: the scenes must not change by a bit.
fn random_motion<R: Rng>(rng: &mut R) -> RigidMotion {
    let q = [(); 4].map(|()| standard_normal(rng));
    let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt().max(1e-12);
    let [w, x, y, z] = q.map(|c| c / norm);
    let rotation = Matrix3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    );
    let translation = Vector3::new(
        standard_normal(rng),
        standard_normal(rng),
        1.0 + rng.random::<f64>(),
    );
    RigidMotion {
        rotation,
        translation,
    }
}

/// Uniform in `0..bound` by scaling a uniform draw (not `random_range`,
/// which draws differently).
fn below<R: Rng>(rng: &mut R, bound: usize) -> usize {
    (rng.random::<f64>() * bound as f64) as usize % bound.max(1)
}

fn graph(positions: &[[f64; 3]], features: &[Vec<f32>]) -> Result<SceneGraph, GraphError> {
    let objects = positions
        .iter()
        .zip(features)
        .enumerate()
        .map(|(k, (p, f))| SceneObject::new(k as u64, *p, f.clone()))
        .collect();
    SceneGraph::new(objects, None, &Limits::default())
}
