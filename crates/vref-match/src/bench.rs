//! Solver benchmark: synthetic rigid scenes of an exact size and a timing
//! loop that reports percentiles. Timings are measured here and printed by
//! the caller (`vref bench solver`); nothing here asserts a duration.

use std::time::Instant;

use vref_scene::{GraphError, Limits, PairError, SceneGraph, SceneObject, ScenePair, Side};

use crate::engine::Engine;
use crate::{MatchError, Method, Params, Tier};

/// Extent of the synthetic workspace box, metres (a table top).
const BOX: [f64; 3] = [0.6, 0.4, 0.2];
/// Standard deviation of the robot's position noise, metres, unless
/// stated otherwise ([`Scenes::noise`]).
pub const POSITION_NOISE: f64 = 0.002;
/// Appearance feature dimension (as the moi preset's histograms).
const FEATURE_DIM: usize = 48;
/// Standard deviation of the robot's feature noise, per component.
const FEATURE_NOISE: f64 = 0.05;
/// How far the moved object of an incremental step travels, metres.
const MOVE_STEP: f64 = 0.05;
/// Distinct scenes cycled through by the repeats, so that one lucky scene
/// does not decide the figures.
const DISTINCT_SCENES: usize = 8;

/// Why a benchmark could not run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BenchError {
    #[error("a benchmark scene needs at least 2 objects, got {0}")]
    TooFewObjects(usize),
    #[error("a benchmark needs at least 1 repeat")]
    NoRepeats,
    #[error("position noise must be finite and at least 0 metres, got {0}")]
    BadNoise(f64),
    #[error("building a synthetic scene: {0}")]
    Scene(#[from] GraphError),
    #[error("building a synthetic scene pair: {0}")]
    Pair(#[from] PairError),
    #[error(transparent)]
    Match(#[from] MatchError),
}

/// What is timed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Mode {
    /// Affinities, solve and Hungarian of a new scene.
    Full,
    /// The engine's update and solve after one human object of a solved
    /// scene moved.
    Incremental,
}

impl Mode {
    pub fn name(self) -> &'static str {
        match self {
            Mode::Full => "full",
            Mode::Incremental => "incremental",
        }
    }
}

/// The synthetic scenes a benchmark times: `objects` per view, from
/// `seed`, the robot view's positions off by `noise` (standard deviation
/// per axis, metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scenes {
    pub objects: usize,
    pub seed: u64,
    pub noise: f64,
    /// Whether both views carry their up vectors ([`RigidScene::upright`]).
    pub up: bool,
}

impl Scenes {
    /// The default scenes: [`POSITION_NOISE`].
    pub fn new(objects: usize, seed: u64) -> Self {
        Self {
            objects,
            seed,
            noise: POSITION_NOISE,
            up: false,
        }
    }
}

/// Percentiles of one method, size and mode.
#[derive(Debug, Clone, PartialEq)]
pub struct Timing {
    pub method: Method,
    pub tier: Tier,
    pub objects: usize,
    /// The robot view's position noise, metres.
    pub noise: f64,
    pub mode: Mode,
    pub median_us: f64,
    pub p99_us: f64,
    /// Median iteration count of the method's main loop.
    pub iterations: usize,
}

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
    /// The rotation taking human positions to robot positions.
    rotation: [[f64; 3]; 3],
}

impl RigidScene {
    /// The same `(objects, seed)` always gives the same scene.
    pub fn new(objects: usize, seed: u64) -> Result<Self, BenchError> {
        Self::with_noise(objects, seed, POSITION_NOISE)
    }

    /// [`RigidScene::new`] with the robot's positions off by `noise`
    /// (standard deviation per axis, metres) instead of [`POSITION_NOISE`];
    /// the same draws otherwise.
    pub fn with_noise(objects: usize, seed: u64, noise: f64) -> Result<Self, BenchError> {
        if objects < 2 {
            return Err(BenchError::TooFewObjects(objects));
        }
        if !(noise.is_finite() && noise >= 0.0) {
            return Err(BenchError::BadNoise(noise));
        }
        let mut rng = SplitMix::new(seed ^ (objects as u64).rotate_left(32));
        let positions: Vec<[f64; 3]> = (0..objects)
            .map(|_| BOX.map(|extent| extent * rng.unit()))
            .collect();
        let features: Vec<Vec<f32>> = (0..objects)
            .map(|_| (0..FEATURE_DIM).map(|_| rng.unit() as f32).collect())
            .collect();
        let human = graph(&positions, &features)?;
        let motion = Rigid::random(&mut rng);
        let mut order: Vec<usize> = (0..objects).collect();
        for k in (1..objects).rev() {
            order.swap(k, rng.below(k + 1));
        }
        let robot_positions: Vec<[f64; 3]> = order
            .iter()
            .map(|&k| motion.apply(positions[k]).map(|c| c + noise * rng.normal()))
            .collect();
        let robot_features: Vec<Vec<f32>> = order
            .iter()
            .map(|&k| {
                features[k]
                    .iter()
                    .map(|&f| (f64::from(f) + FEATURE_NOISE * rng.normal()).max(0.0) as f32)
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
            rotation: motion.rotation,
        })
    }

    /// The scene with both views' up vectors: the human view's z, and
    /// where the motion turns it in the robot's.
    pub fn upright(self) -> Result<Self, BenchError> {
        let up = self.rotation.map(|row| row[2]);
        Ok(Self {
            human: self.human.clone().with_up(Some([0.0, 0.0, 1.0]))?,
            robot: self.robot.clone().with_up(Some(up))?,
            ..self
        })
    }

    /// The scene as a dataset scene pair, with its ground truth (every
    /// object is seen by both views; ids are indices in each view).
    pub fn pair(&self, name: String) -> Result<ScenePair, BenchError> {
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

    /// The scene after human object `index % n` moved `MOVE_STEP` along a
    /// direction drawn from `seed`; the robot view is unchanged, as if the
    /// headset saw the move first.
    pub fn moved(&self, index: usize, seed: u64) -> Result<Self, BenchError> {
        let mut rng = SplitMix::new(seed);
        let mut positions = self.positions.clone();
        let k = index % positions.len();
        let direction = [rng.normal(), rng.normal(), rng.normal()];
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
            rotation: self.rotation,
        })
    }
}

/// Times `repeats` solves of `method` in `tier` on `objects`-object scenes,
/// through the matcher's [`Engine`]: a full solve is a new engine given
/// both views; an incremental one is the update of the moved view and the
/// solve of an engine that had solved the scene before (not timed).
pub fn time_solver(
    method: Method,
    tier: Tier,
    spec: Scenes,
    mode: Mode,
    params: &Params,
    repeats: usize,
) -> Result<Timing, BenchError> {
    if repeats == 0 {
        return Err(BenchError::NoRepeats);
    }
    let Scenes {
        objects,
        seed,
        noise,
        up,
    } = spec;
    let scenes = (0..DISTINCT_SCENES.min(repeats))
        .map(|s| {
            let scene = RigidScene::with_noise(objects, seed.wrapping_add(s as u64), noise)?;
            if up { scene.upright() } else { Ok(scene) }
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut micros = Vec::with_capacity(repeats);
    let mut iterations = Vec::with_capacity(repeats);
    for r in 0..repeats {
        let base = &scenes[r % scenes.len()];
        let mut engine = Engine::new(method, tier, *params)?;
        let timed = match mode {
            Mode::Full => {
                let start = Instant::now();
                engine.update(Side::Human, &base.human)?;
                engine.update(Side::Robot, &base.robot)?;
                let iterations = engine.solve()?.0.iterations;
                (start.elapsed(), iterations)
            }
            Mode::Incremental => {
                let moved = base.moved(r, seed.wrapping_mul(31).wrapping_add(r as u64))?;
                engine.update(Side::Human, &base.human)?;
                engine.update(Side::Robot, &base.robot)?;
                engine.solve()?;
                let start = Instant::now();
                engine.update(Side::Human, &moved.human)?;
                let iterations = engine.solve()?.0.iterations;
                (start.elapsed(), iterations)
            }
        };
        micros.push(timed.0.as_secs_f64() * 1e6);
        iterations.push(timed.1);
    }
    micros.sort_by(f64::total_cmp);
    iterations.sort_unstable();
    Ok(Timing {
        method,
        tier,
        objects,
        noise,
        mode,
        median_us: percentile(&micros, 0.5),
        p99_us: percentile(&micros, 0.99),
        iterations: iterations[iterations.len() / 2],
    })
}

/// Nearest-rank percentile (vref_measure's one definition) of sorted,
/// non-empty `values`; 0 for none.
fn percentile(sorted: &[f64], q: f64) -> f64 {
    vref_measure::percentile(sorted, q).unwrap_or(0.0)
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

/// A rotation (from a unit quaternion) and a translation.
struct Rigid {
    rotation: [[f64; 3]; 3],
    translation: [f64; 3],
}

impl Rigid {
    fn random(rng: &mut SplitMix) -> Self {
        let q = [rng.normal(), rng.normal(), rng.normal(), rng.normal()];
        let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt().max(1e-12);
        let [w, x, y, z] = q.map(|c| c / norm);
        let rotation = [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - w * z),
                2.0 * (x * z + w * y),
            ],
            [
                2.0 * (x * y + w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - w * x),
            ],
            [
                2.0 * (x * z - w * y),
                2.0 * (y * z + w * x),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ];
        let translation = [rng.normal(), rng.normal(), 1.0 + rng.unit()];
        Self {
            rotation,
            translation,
        }
    }

    fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let mut out = self.translation;
        for (o, row) in out.iter_mut().zip(&self.rotation) {
            *o += row.iter().zip(p).map(|(r, c)| r * c).sum::<f64>();
        }
        out
    }
}

/// SplitMix64: tiny, seedable and platform-independent, which is all a
/// benchmark scene needs (no dependency on a random-number crate).
struct SplitMix(u64);

impl SplitMix {
    fn new(seed: u64) -> Self {
        Self(seed)
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn below(&mut self, bound: usize) -> usize {
        (self.unit() * bound as f64) as usize % bound.max(1)
    }

    /// Standard normal (Box-Muller).
    fn normal(&mut self) -> f64 {
        let u = 1.0 - self.unit();
        let v = self.unit();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    fn distances(g: &SceneGraph) -> Vec<f64> {
        let o = g.objects();
        let mut d: Vec<f64> = (0..o.len())
            .flat_map(|i| (i + 1..o.len()).map(move |j| (i, j)))
            .map(|(i, j)| (o[i].position - o[j].position).norm())
            .collect();
        d.sort_by(f64::total_cmp);
        d
    }

    #[test]
    fn scenes_have_the_exact_size_and_are_rigid_up_to_noise() {
        let scene = RigidScene::new(12, 3).unwrap();
        assert_eq!((scene.human.len(), scene.robot.len()), (12, 12));
        assert_eq!(scene.human.feature_dim(), FEATURE_DIM);
        for (h, r) in distances(&scene.human).iter().zip(distances(&scene.robot)) {
            assert!((h - r).abs() < 20.0 * POSITION_NOISE, "{h} vs {r}");
        }
        let again = RigidScene::new(12, 3).unwrap();
        assert_eq!(scene.robot, again.robot);
    }

    #[test]
    fn the_pair_carries_the_true_correspondence() {
        let scene = RigidScene::new(9, 4).unwrap();
        let pair = scene.pair("rigid".to_owned()).unwrap();
        assert_eq!(pair.ground_truth.len(), 9);
        for &(h, r) in &pair.ground_truth {
            let hf = &pair.human.objects()[h as usize].feature;
            let rf = &pair.robot.objects()[r as usize].feature;
            let gap: f32 =
                hf.iter().zip(rf).map(|(a, b)| (a - b).abs()).sum::<f32>() / hf.len() as f32;
            assert!(gap < 0.2, "human {h} and robot {r} differ by {gap}");
        }
    }

    #[test]
    fn a_move_changes_one_human_object() {
        let scene = RigidScene::new(10, 5).unwrap();
        let moved = scene.moved(13, 9).unwrap();
        let changed: Vec<usize> = (0..10)
            .filter(|&k| scene.human.objects()[k] != moved.human.objects()[k])
            .collect();
        assert_eq!(changed, vec![3]);
        let step = (scene.human.objects()[3].position - moved.human.objects()[3].position).norm();
        assert!((step - MOVE_STEP).abs() < 1e-9);
    }

    #[test]
    fn rrwm_recovers_the_rigid_correspondence() {
        let scene = RigidScene::new(10, 1).unwrap();
        let problem = crate::Problem::new(&scene.human, &scene.robot, 0.01).unwrap();
        let solution = crate::solve(Method::Rrwm, &problem, &Params::default()).unwrap();
        let pairs = solution.id_pairs(&scene.human, &scene.robot);
        // The robot objects are a shuffled copy: their positions tell the
        // permutation back.
        let right = pairs
            .iter()
            .filter(|&&(h, r)| {
                let hp = scene.human.objects()[h as usize].position;
                let rp = scene.robot.objects()[r as usize].position;
                let hd = distances_from(&scene.human, hp);
                let rd = distances_from(&scene.robot, rp);
                hd.iter().zip(&rd).all(|(a, b)| (a - b).abs() < 0.02)
            })
            .count();
        assert_eq!(right, 10);
    }

    fn distances_from(g: &SceneGraph, p: nalgebra::Point3<f64>) -> Vec<f64> {
        let mut d: Vec<f64> = g
            .objects()
            .iter()
            .map(|o| (o.position - p).norm())
            .collect();
        d.sort_by(f64::total_cmp);
        d
    }

    #[test]
    fn timing_reports_percentiles_and_refuses_bad_input() {
        for tier in Tier::ALL {
            let t = time_solver(
                Method::Sm,
                tier,
                Scenes::new(6, 1),
                Mode::Incremental,
                &Params::default(),
                3,
            )
            .unwrap();
            assert!(t.median_us > 0.0 && t.p99_us >= t.median_us);
            assert!(t.iterations > 0);
            assert_eq!(t.tier, tier);
        }
        assert_eq!(
            time_solver(
                Method::Sm,
                Tier::Exact,
                Scenes::new(6, 1),
                Mode::Full,
                &Params::default(),
                0,
            ),
            Err(BenchError::NoRepeats)
        );
        for noise in [-0.001, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                RigidScene::with_noise(6, 1, noise),
                Err(BenchError::BadNoise(_))
            ));
        }
        // More noise moves the same draws farther: the scene is otherwise
        // the same.
        let (a, b) = (
            RigidScene::new(6, 1).unwrap(),
            RigidScene::with_noise(6, 1, 0.02).unwrap(),
        );
        assert_eq!(a.human, b.human);
        assert_ne!(a.robot, b.robot);
        assert_eq!(
            RigidScene::new(1, 0).err(),
            Some(BenchError::TooFewObjects(1))
        );
    }

    #[test]
    fn percentile_is_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(&v, 0.5), 50.0);
        assert_eq!(percentile(&v, 0.99), 99.0);
        assert_eq!(percentile(&[7.0], 0.99), 7.0);
    }
}
