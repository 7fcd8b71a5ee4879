//! `rigid`: vref's own method. Both views are rigid snapshots of one 3D
//! scene, so a single proper rotation and translation maps the human
//! view onto the robot's. The method finds it by RANSAC over candidate
//! pairs seeded by appearance, verifies every pair against it, and assigns
//! with a cost for leaving an object without a partner, so that objects
//! one camera alone sees stay unmatched. Its confidence is a calibrated
//! probability that the row's answer (a partner, or none) is right.

use nalgebra::Point3;
use serde::{Deserialize, Serialize};

use crate::calibration::Calibration;
use crate::rigid::{RigidMotion, median_spacing};
use crate::{MatchError, Params, Problem, Solution, hungarian_max};

/// Constants of the `rigid` method.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RigidParams {
    /// Appearance enters as `exp((a - best a of the row) / temperature)`:
    /// a likelihood relative to the row's most similar object.
    pub appearance_temperature: f64,
    /// Robot objects per human object that hypotheses are drawn from,
    /// the most similar in appearance first.
    pub candidates: usize,
    /// Distance-consistent hypotheses scored.
    pub hypotheses: usize,
    /// Residual scale as a multiple of the robot view's median distance
    /// between nearest neighbours: position error and object spacing grow
    /// together with the range a camera works at (centimetres on a table,
    /// decimetres on a floor), so one factor serves both.
    pub sigma_factor: f64,
    /// Where the sensors state each object's position error, it is the
    /// error along the object's ray (views in camera frames), or combined
    /// with sigma in every direction (other views). False: ignored, as
    /// for dataset files, which state none.
    pub stated_errors: bool,
    /// An RGB-D camera's depth error as a share of the range, where the
    /// sensors state none: it lies along the ray from the camera (the
    /// origin of a view's frame), so a pair's residual is weighed in a
    /// metric stretched along both objects' rays, and errs far less in
    /// every other direction (`lateral_factor`). Used for views in front of
    /// their camera (every z > 0); 0 treats every direction alike (sigma).
    pub depth_error: f64,
    /// With the depth-error model: the scale of the error in every
    /// direction besides, as a multiple of the median nearest-neighbour
    /// distance (smaller than `sigma_factor`, which must cover the depth
    /// error too).
    pub lateral_factor: f64,

    /// Cost of leaving a human object without a partner, in the units of
    /// the pair cost `-ln(appearance likelihood) + r^2 / (2 sigma^2)`.
    pub unmatched_cost: f64,
    /// The search ends early at a hypothesis whose score reaches this
    /// share of the largest possible (every object of the smaller view
    /// explained with zero cost).
    pub decisive_share: f64,
    /// Hypotheses scored before the search may end early, for a scene of
    /// 8 x 8 objects; scaled by 64 / (n m) for others. In a scene of a few
    /// objects a wrong motion can explain nearly everything too (and its
    /// hypotheses are cheap); in a large one that is ever less likely (and
    /// each hypothesis costs n m).
    pub decisive_after: usize,
    /// Samples with short edges are drawn too whenever the search with
    /// long edges found no decisive motion (false: only when it found too
    /// few motions to keep).
    pub short_edges_always: bool,
    /// Best hypotheses of the search that are locally optimised (re-fitted
    /// to the pairs they explain) before the best is chosen.
    pub local_optimisations: usize,
    /// Re-fits of the motion on the assigned pairs after the search.
    pub refinements: usize,
    /// Score difference (in nats: scores are log-likelihood gains) that
    /// makes the best motion e times likelier than the runner-up.
    pub motion_temperature: f64,
    /// Motions that pair objects otherwise weighed against the best (1:
    /// the runner-up alone).
    pub rivals: usize,
    /// A partner that the runner-up motion pairs otherwise and whose raw
    /// share (its row's softmax share times the best motion's probability)
    /// is below this is not given: the object is answered "no partner".
    /// 0 never abstains.
    pub abstain_share: f64,
    /// Abstaining needs a real dispute: the best motion's probability
    /// against the runner-up must be below this (1 abstains whenever the
    /// runner-up pairs the row otherwise). A row share lowered by look-alike
    /// neighbours alone is not a dispute between motions.
    pub abstain_motion: f64,
    /// When abstention would leave a scene without any partner, the most
    /// confident disputed partner is given all the same: an empty answer is
    /// precision 0 and tells the robot nothing.
    pub never_empty: bool,
    /// Refuse motions that put the two cameras on opposite sides of the
    /// plane the objects stand on (see `Side`).
    pub same_side: bool,
    /// Seed of the hypothesis sampler (answers are deterministic).
    pub seed: u64,
    /// Raw row share and fit quality to probability.
    pub calibration: Calibration,
}

impl Default for RigidParams {
    fn default() -> Self {
        Self {
            appearance_temperature: 0.1,
            candidates: 6,
            hypotheses: 200,
            sigma_factor: 0.4,
            stated_errors: true,
            depth_error: 0.065,
            lateral_factor: 0.2,
            unmatched_cost: 4.5,
            decisive_share: 0.8,
            decisive_after: 100,
            short_edges_always: true,
            local_optimisations: 8,
            refinements: 3,
            motion_temperature: 1.0,
            rivals: 7,
            abstain_share: 0.65,
            abstain_motion: 0.95,
            never_empty: true,
            same_side: true,
            seed: 0x5eed,
            calibration: Calibration::default(),
        }
    }
}

impl RigidParams {
    pub(crate) fn validate(&self) -> Result<(), MatchError> {
        for (name, value) in [
            ("rigid.appearance_temperature", self.appearance_temperature),
            ("rigid.sigma_factor", self.sigma_factor),
            ("rigid.unmatched_cost", self.unmatched_cost),
            ("rigid.decisive_share", self.decisive_share),
            ("rigid.motion_temperature", self.motion_temperature),
            ("rigid.lateral_factor", self.lateral_factor),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(MatchError::BadParameter {
                    name,
                    value,
                    expected: "positive and finite",
                });
            }
        }
        for (name, count) in [
            ("rigid.candidates", self.candidates),
            ("rigid.hypotheses", self.hypotheses),
        ] {
            if count == 0 {
                return Err(MatchError::BadParameter {
                    name,
                    value: 0.0,
                    expected: "at least 1",
                });
            }
        }
        if !(self.depth_error.is_finite() && self.depth_error >= 0.0) {
            return Err(MatchError::BadParameter {
                name: "rigid.depth_error",
                value: self.depth_error,
                expected: "zero or positive and finite",
            });
        }
        if !(0.0..=1.0).contains(&self.abstain_motion) {
            return Err(MatchError::BadParameter {
                name: "rigid.abstain_motion",
                value: self.abstain_motion,
                expected: "in [0, 1]",
            });
        }
        if !(0.0..=1.0).contains(&self.abstain_share) {
            return Err(MatchError::BadParameter {
                name: "rigid.abstain_share",
                value: self.abstain_share,
                expected: "in [0, 1]",
            });
        }
        let c = &self.calibration;
        if ![c.bias, c.slope, c.no_partner_shift]
            .iter()
            .all(|v| v.is_finite())
        {
            return Err(MatchError::BadParameter {
                name: "rigid.calibration",
                value: f64::NAN,
                expected: "finite constants",
            });
        }
        Ok(())
    }
}

/// Minimal samples tried per hypothesis scored; most fail the cheap
/// distance check, so this bounds the search when nothing is consistent.
const ATTEMPTS_PER_HYPOTHESIS: usize = 50;
/// Score of a column a row must never take in the padded assignment.
const FORBIDDEN: f64 = -1e12;
/// Robot objects this much below a row's best appearance log-likelihood
/// (a tenth of its likelihood) are still candidates.
const CANDIDATE_LOG_GAP: f64 = std::f64::consts::LN_10;
/// Re-fits per locally optimised hypothesis (each must raise its score).
const LOCAL_REFITS: usize = 3;
/// The search's shortcut round scores at most this many times the
/// hypotheses a decisive motion waits for (all `hypotheses` up to scenes
/// of 16 x 16 objects).
const SHORTCUT_PATIENCE: usize = 8;

/// The per-pair costs of one motion (or of appearance alone).
struct Costs<'a> {
    problem: &'a Problem,
    log_g: &'a [f64],
    inv_two_sigma2: f64,
    /// Per pair, when the sensors state position errors: `1 / (2 s^2)`
    /// with `s^2 = sigma^2 + var_i + var_j`. The residual is weighed in
    /// units of its own expected error (a Mahalanobis gate, as trackers
    /// gate detections), without the Gaussian's normalisation: with it, an
    /// object far from the camera would cost more than "no partner" even
    /// at its exact place (on the feeds' world of 64 objects it left 98% of
    /// the objects unmatched).
    stated: Option<Vec<f64>>,
    /// Robot positions by coordinate, so that a row of costs is one
    /// vectorisable pass (the search computes thousands of rows).
    robot_xyz: [Vec<f64>; 3],
    rays: Option<Rays>,
    /// The residual scale of a typical pair.
    typical: f64,
}

/// Each object's ray from its camera and depth variance along it.
struct Rays {
    /// Unit rays of the human objects (human frame) and their variances.
    human: Vec<(nalgebra::Vector3<f64>, f64)>,
    /// Robot rays by coordinate, and their variances.
    robot_u: [Vec<f64>; 3],
    robot_var: Vec<f64>,
    /// Lateral variance (sigma squared).
    lateral: f64,
}

impl Rays {
    /// The rays of views in front of their cameras (every z > 0): their
    /// variance along the ray is the stated error where the sensors state
    /// one (all of it: an RGB-D camera's depth error dominates and lies
    /// along the ray), else `depth_error` times the range, squared. `None`
    /// for other views or when neither applies.
    fn of(problem: &Problem, rp: &RigidParams, lateral_sigma: f64) -> Option<Self> {
        let in_front = |ps: &[Point3<f64>]| ps.iter().all(|p| p.z > 0.0);
        if !(in_front(&problem.human_positions) && in_front(&problem.robot_positions)) {
            return None;
        }
        let stated = rp.stated_errors && has_stated_errors(problem);
        if !(stated || rp.depth_error > 0.0) {
            return None;
        }
        let rays = |points: &[Point3<f64>], variances: &[f64]| -> Vec<_> {
            points
                .iter()
                .enumerate()
                .map(|(k, p)| {
                    let range = p.coords.norm();
                    let along = if stated {
                        // The mean over the axes times three: the total.
                        3.0 * variance(variances, k)
                    } else {
                        (rp.depth_error * range).powi(2)
                    };
                    (p.coords / range, along)
                })
                .collect()
        };
        let human = rays(&problem.human_positions, &problem.human_variances);
        let robot = rays(&problem.robot_positions, &problem.robot_variances);
        let axis = |k: usize| robot.iter().map(|(u, _)| u[k]).collect();
        Some(Self {
            human,
            robot_u: [axis(0), axis(1), axis(2)],
            robot_var: robot.iter().map(|(_, v)| *v).collect(),
            lateral: lateral_sigma * lateral_sigma,
        })
    }

    /// Half the squared Mahalanobis length of residual `r` of human object
    /// `i` (ray `w` in the robot frame, `alpha` = h / (lateral + h)) against
    /// robot object `j`: the covariance is `lateral I + h w w^T + c u u^T`,
    /// inverted by Sherman-Morrison twice.
    #[inline]
    fn half_distance2(&self, r: [f64; 3], w: [f64; 3], alpha: f64, j: usize) -> f64 {
        let u = [self.robot_u[0][j], self.robot_u[1][j], self.robot_u[2][j]];
        half_mahalanobis2(r, w, alpha, u, self.robot_var[j], 1.0 / self.lateral)
    }

    /// [`Rays::half_distance2`] of human object `i`, at `moved`, against
    /// every robot object (`xyz`: their positions by coordinate), into
    /// `out`: one pass over slices of equal length, which the compiler
    /// vectorises (the search computes thousands of rows).
    fn row(
        &self,
        i: usize,
        motion: &RigidMotion,
        moved: &Point3<f64>,
        xyz: &[Vec<f64>; 3],
        out: &mut [f64],
    ) {
        let m = out.len();
        let (w, alpha) = self.human_ray(i, &motion.rotation);
        let inv = 1.0 / self.lateral;
        let (xs, ys, zs) = (&xyz[0][..m], &xyz[1][..m], &xyz[2][..m]);
        let (ux, uy, uz) = (
            &self.robot_u[0][..m],
            &self.robot_u[1][..m],
            &self.robot_u[2][..m],
        );
        let var = &self.robot_var[..m];
        for k in 0..m {
            let r = [moved.x - xs[k], moved.y - ys[k], moved.z - zs[k]];
            out[k] = half_mahalanobis2(r, w, alpha, [ux[k], uy[k], uz[k]], var[k], inv);
        }
    }

    /// Human object `i`'s ray under `rotation` and its `alpha`.
    fn human_ray(&self, i: usize, rotation: &nalgebra::Matrix3<f64>) -> ([f64; 3], f64) {
        let (v, h) = self.human[i];
        let w = rotation * v;
        ([w.x, w.y, w.z], h / (self.lateral + h))
    }
}

/// Half of `r^T C^-1 r` for `C = I / inv + h w w^T + c u u^T` (`alpha`
/// = h / (1 / inv + h)), by Sherman-Morrison twice.
#[inline(always)]
fn half_mahalanobis2(r: [f64; 3], w: [f64; 3], alpha: f64, u: [f64; 3], c: f64, inv: f64) -> f64 {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (rr, wr, ur, wu) = (dot(r, r), dot(w, r), dot(u, r), dot(w, u));
    let a = (rr - alpha * wr * wr) * inv;
    let b = (ur - alpha * wu * wr) * inv;
    let uu = (1.0 - alpha * wu * wu) * inv;
    0.5 * (a - c * b * b / (1.0 + c * uu))
}

impl<'a> Costs<'a> {
    /// The costs of `problem` with residual scales from the robot view's
    /// object `spacing`: the ray model for views in camera frames (with the
    /// sensors' stated errors, else `depth_error`), the stated errors
    /// isotropically for other views that state any, else one isotropic
    /// sigma.
    fn new(problem: &'a Problem, log_g: &'a [f64], spacing: f64, rp: &RigidParams) -> Self {
        let axis = |k: usize| problem.robot_positions.iter().map(|p| p[k]).collect();
        let sigma = rp.sigma_factor * spacing;
        let sigma2 = sigma * sigma;
        let rays = Rays::of(problem, rp, rp.lateral_factor * spacing);
        // Stated errors of views that are not in camera frames: isotropic.
        let stated =
            (rays.is_none() && rp.stated_errors && has_stated_errors(problem)).then(|| {
                let (n, m) = (problem.n, problem.m);
                let mut inv = Vec::with_capacity(n * m);
                for i in 0..n {
                    for j in 0..m {
                        let s2 = sigma2
                            + variance(&problem.human_variances, i)
                            + variance(&problem.robot_variances, j);
                        inv.push(1.0 / (2.0 * s2));
                    }
                }
                inv
            });
        // The search's tolerances follow the typical pair's scale.
        let typical = if stated.is_some() {
            (sigma2 + median(&problem.human_variances) + median(&problem.robot_variances)).sqrt()
        } else if let Some(rays) = &rays {
            let human: Vec<f64> = rays.human.iter().map(|(_, h)| *h).collect();
            (rays.lateral + median(&human) + median(&rays.robot_var)).sqrt()
        } else {
            sigma
        };
        Self {
            problem,
            log_g,
            inv_two_sigma2: 1.0 / (2.0 * sigma2),
            stated,
            robot_xyz: [axis(0), axis(1), axis(2)],
            rays,
            typical,
        }
    }

    /// Costs of human object `i`, moved to `moved`, against every robot
    /// object, into `out` (length m).
    fn row(&self, i: usize, motion: &RigidMotion, out: &mut [f64]) {
        let m = self.problem.m;
        let moved = &motion.apply(&self.problem.human_positions[i]);
        let log_g = &self.log_g[i * m..(i + 1) * m];
        let [xs, ys, zs] = &self.robot_xyz;
        if let Some(rays) = &self.rays {
            rays.row(i, motion, moved, &self.robot_xyz, out);
            for (o, g) in out.iter_mut().zip(log_g) {
                *o -= g;
            }
            return;
        }
        if let Some(inv) = &self.stated {
            let inv = &inv[i * m..(i + 1) * m];
            for (k, o) in out.iter_mut().enumerate() {
                let (dx, dy, dz) = (moved.x - xs[k], moved.y - ys[k], moved.z - zs[k]);
                *o = (dx * dx + dy * dy + dz * dz) * inv[k] - log_g[k];
            }
            return;
        }
        let inv = self.inv_two_sigma2;
        for ((((o, &g), &x), &y), &z) in out.iter_mut().zip(log_g).zip(xs).zip(ys).zip(zs) {
            let (dx, dy, dz) = (moved.x - x, moved.y - y, moved.z - z);
            *o = (dx * dx + dy * dy + dz * dz) * inv - g;
        }
    }

    fn pair(
        &self,
        motion: Option<&RigidMotion>,
        moved: Option<&Point3<f64>>,
        i: usize,
        j: usize,
    ) -> f64 {
        let m = self.problem.m;
        let appearance = -self.log_g[i * m + j];
        match (motion, moved) {
            (Some(t), Some(p)) => {
                let d = p - self.problem.robot_positions[j];
                if let Some(rays) = &self.rays {
                    let (w, alpha) = rays.human_ray(i, &t.rotation);
                    return appearance + rays.half_distance2([d.x, d.y, d.z], w, alpha, j);
                }
                let r2 = d.norm_squared();
                let inv = self
                    .stated
                    .as_ref()
                    .map_or(self.inv_two_sigma2, |inv| inv[i * m + j]);
                appearance + r2 * inv
            }
            _ => appearance,
        }
    }

    /// Row-major `n x m` costs under `motion`.
    fn matrix(&self, motion: Option<&RigidMotion>) -> Vec<f64> {
        let (n, m) = (self.problem.n, self.problem.m);
        let mut out = Vec::with_capacity(n * m);
        for i in 0..n {
            let moved = motion.map(|t| t.apply(&self.problem.human_positions[i]));
            for j in 0..m {
                out.push(self.pair(motion, moved.as_ref(), i, j));
            }
        }
        out
    }
}

pub(super) fn solve(problem: &Problem, params: &Params) -> Solution {
    let rp = &params.rigid;
    let (n, m) = (problem.n, problem.m);
    let spacing = median_spacing(&problem.robot_positions).unwrap_or(params.beta.sqrt());
    let log_g = appearance_log_likelihood(problem, rp.appearance_temperature);
    let costs = Costs::new(problem, &log_g, spacing, rp);
    let found = search(&costs, costs.typical, rp);
    let mut motion = found.as_ref().map(|f| f.motion);
    let mut cost = costs.matrix(motion.as_ref());
    let mut assignment = assign(&cost, n, m, rp.unmatched_cost);
    let mut iterations = 0;
    let mut converged = motion.is_none();
    if motion.is_some() {
        for _ in 0..rp.refinements {
            iterations += 1;
            let Some(refit) = fit_assigned(problem, &assignment) else {
                break;
            };
            motion = Some(refit);
            cost = costs.matrix(motion.as_ref());
            let next = assign(&cost, n, m, rp.unmatched_cost);
            let same = next == assignment;
            assignment = next;
            if same {
                converged = true;
                break;
            }
        }
    }
    let (soft, unmatched) = row_shares(&cost, n, m, rp.unmatched_cost);

    // The rival motions: each is weighed against the best by its score,
    // and a row's answer is only as sure as the motions that give it.
    let mut weights = Vec::new();
    let mut rivals = Vec::new();
    if let Some(f) = &found {
        for &(score, alt) in &f.alternatives {
            let w = ((score - f.score) / rp.motion_temperature).exp();
            if w > 1e-9 {
                weights.push(w);
                rivals.push(assign(&costs.matrix(Some(&alt)), n, m, rp.unmatched_cost));
            }
        }
    }
    let total = 1.0 + weights.iter().sum::<f64>();
    let p_best = 1.0 / total;
    let mut confidence = Vec::with_capacity(n);
    // The best of the partners abstention takes back, in case it takes
    // them all: (raw share, row, partner).
    let mut withdrawn: Option<(f64, usize, usize)> = None;
    let disputed = p_best < rp.abstain_motion;
    for i in 0..n {
        let against: f64 = rivals
            .iter()
            .zip(&weights)
            .filter(|(alt, _)| alt[i] != assignment[i])
            .map(|(_, w)| w)
            .sum();
        let agrees = against == 0.0;
        let motion_share = 1.0 - against / total;
        let mut raw = motion_share
            * match assignment[i] {
                Some(j) => soft[i * m + j],
                None => unmatched[i],
            };
        // Abstaining: a partner the runner-up motion disputes and that is
        // this unsure is not given (precision); the object is answered "no
        // partner" with that answer's share. Decided on the raw share, so
        // that the calibration is fitted to the answers as finally given.
        if let Some(j) = assignment[i]
            && disputed
            && !agrees
            && raw < rp.abstain_share
        {
            if withdrawn.is_none_or(|(best, _, _)| raw > best) {
                withdrawn = Some((raw, i, j));
            }
            assignment[i] = None;
            raw = unmatched[i];
        }
        confidence.push(raw);
    }
    if rp.never_empty
        && assignment.iter().all(Option::is_none)
        && let Some((raw, i, j)) = withdrawn
    {
        assignment[i] = Some(j);
        confidence[i] = raw;
    }
    for (c, a) in confidence.iter_mut().zip(&assignment) {
        *c = rp.calibration.probability(*c, a.is_none());
    }
    Solution {
        soft,
        assignment,
        confidence,
        iterations,
        converged,
    }
}

/// `(a - max of the row) / temperature`: the log of an appearance
/// likelihood relative to the row's best; all 0 without features.
fn appearance_log_likelihood(problem: &Problem, temperature: f64) -> Vec<f64> {
    let m = problem.m;
    let mut out = Vec::with_capacity(problem.len());
    for row in problem.appearance.chunks(m) {
        let best = row.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        out.extend(row.iter().map(|&a| (a - best) / temperature));
    }
    out
}

/// Indices of `points` sorted by their coordinates, x first.
fn position_order(points: &[Point3<f64>]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        let (p, q) = (&points[a], &points[b]);
        p.x.total_cmp(&q.x)
            .then(p.y.total_cmp(&q.y))
            .then(p.z.total_cmp(&q.z))
            .then(a.cmp(&b))
    });
    order
}

/// `rank[k]`: where index `k` stands in `order`.
fn ranks(order: &[usize]) -> Vec<usize> {
    let mut rank = vec![0; order.len()];
    for (r, &k) in order.iter().enumerate() {
        rank[k] = r;
    }
    rank
}

/// The best-scoring proper motion among hypotheses fitted to three
/// distance-consistent candidate pairs; `None` when either view has fewer
/// than three objects or no sample is consistent.
fn search(costs: &Costs<'_>, sigma: f64, rp: &RigidParams) -> Option<Found> {
    let problem = costs.problem;
    let (n, m) = (problem.n, problem.m);
    if n < 3 || m < 3 {
        return None;
    }
    let hp = &problem.human_positions;
    let rpos = &problem.robot_positions;
    // The samples are drawn over objects in an order of their positions,
    // not of the lists they came in, so that relabelling a view draws the
    // same hypotheses and gives the same answer.
    let human_order = position_order(hp);
    let robot_rank = ranks(&position_order(rpos));
    let mut candidates = candidate_columns(costs.log_g, n, m, rp.candidates);
    for row in &mut candidates {
        row.sort_by_key(|&col| robot_rank[col]);
    }
    // Distances may disagree by the noise of two positions on each side.
    let tolerance = 3.0 * sigma;
    let mut rng = SplitMix(rp.seed ^ ((n as u64) << 32) ^ m as u64);
    let mut top: Vec<(f64, RigidMotion)> = Vec::new();
    let max_attempts = rp.hypotheses.saturating_mul(ATTEMPTS_PER_HYPOTHESIS);
    let mut consistent: Vec<usize> = Vec::with_capacity(m);
    let mut scratch = Scratch::default();
    let side = Side::of(rpos);
    let probes = probe_points(hp);
    let same = |a: &RigidMotion, b: &RigidMotion| same_motion(a, b, &probes, 2.0 * sigma);
    // A motion that explains nearly every object nearly perfectly leaves
    // nothing for further hypotheses to find.
    let decisive = rp.decisive_share * rp.unmatched_cost * n.min(m) as f64;
    let decisive_after = rp.decisive_after.saturating_mul(64).div_ceil(n * m);
    // Sample edges shorter than the tolerance give poorly determined
    // rotations and are avoided, unless a sparse scene has too few samples
    // without them to fill the kept few.
    let keep = rp.local_optimisations.max(1);
    let mut settled = false;
    // Rounds of (distance tolerance, shortest edge, shortcut). Under the
    // depth-error model the tolerance must admit errors along the rays that
    // are large against the spacing, which leaves guided sampling little to
    // go on. A first round at the lateral scale alone settles scenes whose
    // positions are better than the model assumes at once; it is a
    // shortcut only: unless it settles the scene it is forgotten (its own
    // generator, its motions dropped), so it never changes the answer to a
    // scene it does not settle.
    let mut rounds = Vec::with_capacity(3);
    if let Some(rays) = &costs.rays {
        let precise = 3.0 * rays.lateral.sqrt();
        rounds.push((precise, precise, true));
    }
    rounds.extend([(tolerance, tolerance, false), (tolerance, 0.0, false)]);
    let mut shortcut_rng = SplitMix(!rng.0);
    for (tolerance, min_edge, shortcut) in rounds {
        // Without a decisive motion the short edges get their turn too: in
        // a scene of a few objects the right triangle may have no edge
        // longer than the tolerance, while wrong ones fill the kept few.
        let short = min_edge == 0.0;
        if settled || (short && !rp.short_edges_always && top.len() >= keep) {
            break;
        }
        let rng = if shortcut {
            &mut shortcut_rng
        } else {
            &mut rng
        };
        let fits = |(i, a): (usize, usize), (j, b): (usize, usize)| {
            let dh = (hp[i] - hp[j]).norm();
            let dr = (rpos[a] - rpos[b]).norm();
            i != j && a != b && dh > min_edge && (dh - dr).abs() <= tolerance
        };
        let mut scored = 0;
        let mut attempts = 0;

        // The shortcut is worth a few of the hypotheses a decisive motion
        // must wait for: in a large scene that it does not settle at once
        // (crowded views from afar) it would be wasted work.
        let budget = if shortcut {
            rp.hypotheses
                .min(decisive_after.saturating_mul(SHORTCUT_PATIENCE))
        } else {
            rp.hypotheses
        };
        while scored < budget && attempts < max_attempts {
            attempts += 1;
            // Guided sampling: the second and third pairs are drawn only among
            // the candidates whose distances agree with the pairs drawn before,
            // so that a right first pair is likely to grow into a right sample
            // even when a row has many look-alike candidates.
            let i = human_order[rng.below(n)];
            let first = (i, candidates[i][rng.below(candidates[i].len())]);
            let mut s = [first; 3];
            let mut complete = true;
            for k in 1..3 {
                let row = human_order[rng.below(n)];
                consistent.clear();
                consistent.extend(
                    candidates[row]
                        .iter()
                        .copied()
                        .filter(|&col| s[..k].iter().all(|&p| fits(p, (row, col)))),
                );
                if consistent.is_empty() {
                    complete = false;
                    break;
                }
                s[k] = (row, consistent[rng.below(consistent.len())]);
            }
            if !complete {
                continue;
            }
            let from = s.map(|(i, _)| hp[i]);
            let to = s.map(|(_, j)| rpos[j]);
            let Some(motion) = RigidMotion::fit(&from, &to, &[1.0; 3]) else {
                continue;
            };
            if rp.same_side && !side.allows(&motion) {
                continue;
            }
            scored += 1;
            // Only a hypothesis that can enter the kept few is scored fully.
            let keep = rp.local_optimisations.max(1);
            let beat = if top.len() < keep {
                f64::NEG_INFINITY
            } else {
                top.last().map_or(f64::NEG_INFINITY, |(s, _)| *s)
            };
            if let Some((score, _)) = greedy(costs, &motion, rp.unmatched_cost, beat, &mut scratch)
            {
                keep_best(&mut top, keep, score, motion, same);
                if score >= decisive && scored >= decisive_after {
                    settled = true;
                    break;
                }
            }
        }
        if shortcut && !settled {
            top.clear();
        }
    }
    // Local optimisation: a motion fitted to three noisy pairs is only
    // roughly right, so the best few are re-fitted to the pairs they
    // explain before they are compared.
    let mut refined: Vec<(f64, RigidMotion)> = Vec::with_capacity(top.len());
    for (mut score, mut motion) in top {
        for _ in 0..LOCAL_REFITS {
            let Some((_, pairs)) = greedy(
                costs,
                &motion,
                rp.unmatched_cost,
                f64::NEG_INFINITY,
                &mut scratch,
            ) else {
                break;
            };
            let Some(refit) = fit_pairs(problem, &pairs) else {
                break;
            };
            let Some((refit_score, _)) =
                greedy(costs, &refit, rp.unmatched_cost, score, &mut scratch)
            else {
                break;
            };
            if refit_score <= score {
                break;
            }
            (score, motion) = (refit_score, refit);
        }
        refined.push((score, motion));
    }
    refined.sort_by(|a, b| b.0.total_cmp(&a.0));
    let (score, motion) = *refined.first()?;
    // The runner-up must pair objects otherwise: a motion that the local
    // optimisation left short of the same pairs' fit is the best motion
    // again, only fitted worse, and would dispute nothing real.
    let pairs_of = |m: &RigidMotion, scratch: &mut Scratch| {
        greedy(costs, m, rp.unmatched_cost, f64::NEG_INFINITY, scratch).map(|(_, mut p)| {
            p.sort_unstable();
            p
        })
    };
    let mut seen = vec![pairs_of(&motion, &mut scratch)];
    let mut alternatives = Vec::new();
    for &(other_score, other) in refined.iter().skip(1) {
        if alternatives.len() >= rp.rivals {
            break;
        }
        if same(&motion, &other) {
            continue;
        }
        let pairs = pairs_of(&other, &mut scratch);
        if !seen.contains(&pairs) {
            seen.push(pairs);
            alternatives.push((other_score, other));
        }
    }
    Some(Found {
        motion,
        score,
        alternatives,
    })
}

/// The search's answer: the best motion, its score, and the best few
/// motions that pair objects otherwise (each differently from the others),
/// with their scores, best first.
struct Found {
    motion: RigidMotion,
    score: f64,
    alternatives: Vec<(f64, RigidMotion)>,
}

/// Inserts `(score, motion)` into `top`, which holds the `k` best
/// distinct motions so far, best first: a motion that places the probe
/// points like one already held replaces it only when it scores higher.
fn keep_best(
    top: &mut Vec<(f64, RigidMotion)>,
    k: usize,
    score: f64,
    motion: RigidMotion,
    same: impl Fn(&RigidMotion, &RigidMotion) -> bool,
) {
    if let Some(at) = top.iter().position(|(_, held)| same(held, &motion)) {
        if top[at].0 >= score {
            return;
        }
        top.remove(at);
    }
    let at = top.partition_point(|(s, _)| *s >= score);
    if at < k {
        top.insert(at, (score, motion));
        top.truncate(k);
    }
}

/// Whether two motions place every probe point within `tolerance` of
/// each other (they name the same correspondences).
fn same_motion(a: &RigidMotion, b: &RigidMotion, probes: &[Point3<f64>], tolerance: f64) -> bool {
    probes
        .iter()
        .all(|p| (a.apply(p) - b.apply(p)).norm_squared() <= tolerance * tolerance)
}

/// How well `motion` explains the scene: each human object's best pair
/// under it, taken greedily by gain over "no partner" with every robot
/// object used once (a cheap stand-in for the assignment). Returns the
/// total gain and the pairs taken, or `None` as soon as the total cannot
/// reach `beat` (each row gains at most `unmatched`). Objects without a
/// partner add nothing instead of dragging a right motion down.
fn greedy(
    costs: &Costs<'_>,
    motion: &RigidMotion,
    unmatched: f64,
    beat: f64,
    scratch: &mut Scratch,
) -> Option<(f64, Vec<(usize, usize)>)> {
    let problem = costs.problem;
    let (n, m) = (problem.n, problem.m);
    scratch.gains.clear();
    scratch.row.resize(m, 0.0);
    let mut bound = unmatched * n as f64;
    for i in 0..n {
        costs.row(i, motion, &mut scratch.row);
        // The two best columns of the row, so that a row whose best is
        // taken can still fall back to its second.
        let mut first = (f64::INFINITY, usize::MAX);
        let mut second = (f64::INFINITY, usize::MAX);
        for (j, &c) in scratch.row.iter().enumerate() {
            if c < second.0 {
                if c < first.0 {
                    second = first;
                    first = (c, j);
                } else {
                    second = (c, j);
                }
            }
        }
        bound -= unmatched - (unmatched - first.0).max(0.0);
        if bound < beat {
            return None;
        }
        for (c, j) in [first, second] {
            if c < unmatched && j != usize::MAX {
                scratch.gains.push((unmatched - c, i, j));
            }
        }
    }
    scratch.gains.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
    scratch.row_used.clear();
    scratch.row_used.resize(n, false);
    scratch.col_used.clear();
    scratch.col_used.resize(m, false);
    let mut total = 0.0;
    let mut pairs = Vec::with_capacity(n.min(m));
    for &(gain, i, j) in &scratch.gains {
        if !scratch.row_used[i] && !scratch.col_used[j] {
            scratch.row_used[i] = true;
            scratch.col_used[j] = true;
            total += gain;
            pairs.push((i, j));
        }
    }
    Some((total, pairs))
}

/// Buffers reused by every [`greedy`] call of one search.
#[derive(Default)]
struct Scratch {
    row: Vec<f64>,
    gains: Vec<(f64, usize, usize)>,
    row_used: Vec<bool>,
    col_used: Vec<bool>,
}

/// The motion fitted to `pairs` of (human, robot) objects; `None` below
/// three pairs.
fn fit_pairs(problem: &Problem, pairs: &[(usize, usize)]) -> Option<RigidMotion> {
    if pairs.len() < 3 {
        return None;
    }
    let from: Vec<_> = pairs
        .iter()
        .map(|&(i, _)| problem.human_positions[i])
        .collect();
    let to: Vec<_> = pairs
        .iter()
        .map(|&(_, j)| problem.robot_positions[j])
        .collect();
    RigidMotion::fit(&from, &to, &vec![1.0; pairs.len()])
}

/// For each human object, the robot objects that hypotheses may pair it
/// with, most similar first: its `k` most similar, and every other whose
/// appearance likelihood is within [`CANDIDATE_LOG_GAP`] of the best (all
/// of them when appearance tells nothing, as without features).
fn candidate_columns(log_g: &[f64], n: usize, m: usize, k: usize) -> Vec<Vec<usize>> {
    (0..n)
        .map(|i| {
            let row = &log_g[i * m..(i + 1) * m];
            let mut order: Vec<usize> = (0..m).collect();
            order.sort_by(|&a, &b| row[b].total_cmp(&row[a]));
            let keep = order
                .iter()
                .enumerate()
                .take_while(|&(rank, &j)| rank < k || row[j] >= -CANDIDATE_LOG_GAP)
                .count();
            order.truncate(keep.max(1));
            order
        })
        .collect()
}

/// Both cameras look at the objects from the same side of the surface
/// they stand on (a table top, a floor). When the robot view's objects lie
/// near a plane with the robot camera clearly off it, a motion that puts
/// the human camera on the other side is a mirror of the scene through
/// that plane, and is refused. Says nothing for scenes far from planar or
/// cameras in their plane (image coordinates with z = 0).
struct Side {
    plane: Option<(Point3<f64>, nalgebra::Vector3<f64>)>,
}

impl Side {
    /// Smallest spread of the objects across the plane, as a share of the
    /// next smallest, below which the scene counts as planar.
    const FLATNESS: f64 = 0.25;

    fn of(points: &[Point3<f64>]) -> Self {
        let none = Self { plane: None };
        if points.len() < 3 {
            return none;
        }
        let c = points
            .iter()
            .fold(nalgebra::Vector3::zeros(), |c, p| c + p.coords)
            / points.len() as f64;
        let cov = points.iter().fold(nalgebra::Matrix3::zeros(), |acc, p| {
            let d = p.coords - c;
            acc + d * d.transpose()
        }) / points.len() as f64;
        let eig = cov.symmetric_eigen();
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
        let (low, mid) = (eig.eigenvalues[order[0]], eig.eigenvalues[order[1]]);
        if !(mid > 0.0 && low.max(0.0).sqrt() <= Self::FLATNESS * mid.sqrt()) {
            return none;
        }
        let mut normal = eig.eigenvectors.column(order[0]).into_owned();
        // Orient the normal towards the robot camera (the origin).
        let camera = -normal.dot(&c);
        if camera.abs() <= 3.0 * mid.sqrt() * Self::FLATNESS {
            return none;
        }
        if camera < 0.0 {
            normal = -normal;
        }
        Self {
            plane: Some((Point3::from(c), normal)),
        }
    }

    /// Whether `motion` keeps the human camera (its origin) on the robot
    /// camera's side of the plane.
    fn allows(&self, motion: &RigidMotion) -> bool {
        self.plane
            .is_none_or(|(c, normal)| normal.dot(&(motion.apply(&Point3::origin()) - c)) > 0.0)
    }
}

/// The human view's extreme points along each axis and its centroid:
/// where two motions that pair objects differently disagree most.
fn probe_points(points: &[Point3<f64>]) -> Vec<Point3<f64>> {
    let mut probes = Vec::with_capacity(7);
    if points.is_empty() {
        return probes;
    }
    let centroid = points
        .iter()
        .fold(nalgebra::Vector3::zeros(), |c, p| c + p.coords)
        / points.len() as f64;
    probes.push(Point3::from(centroid));
    for axis in 0..3 {
        let by = |a: &&Point3<f64>, b: &&Point3<f64>| a[axis].total_cmp(&b[axis]);
        if let (Some(lo), Some(hi)) = (points.iter().min_by(by), points.iter().max_by(by)) {
            probes.push(*lo);
            probes.push(*hi);
        }
    }
    probes
}

/// Whether either view states a position error for some object.
fn has_stated_errors(problem: &Problem) -> bool {
    problem
        .human_variances
        .iter()
        .chain(&problem.robot_variances)
        .any(|&v| v > 0.0)
}

/// Entry `k` of a per-object list that may be empty (nothing stated).
fn variance(list: &[f64], k: usize) -> f64 {
    list.get(k).copied().unwrap_or(0.0)
}

fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied().unwrap_or(0.0)
}

/// The motion re-fitted to the assigned pairs; `None` below three pairs.
fn fit_assigned(problem: &Problem, assignment: &[Option<usize>]) -> Option<RigidMotion> {
    let (from, to): (Vec<_>, Vec<_>) = assignment
        .iter()
        .enumerate()
        .filter_map(|(i, a)| a.map(|j| (problem.human_positions[i], problem.robot_positions[j])))
        .unzip();
    if from.len() < 3 {
        return None;
    }
    RigidMotion::fit(&from, &to, &vec![1.0; from.len()])
}

/// Minimum-cost assignment in which every human object may instead stay
/// unmatched at cost `unmatched`: the robot side is padded with one
/// private "no partner" column per row.
fn assign(cost: &[f64], n: usize, m: usize, unmatched: f64) -> Vec<Option<usize>> {
    let width = m + n;
    let mut scores = vec![FORBIDDEN; n * width];
    for i in 0..n {
        for j in 0..m {
            scores[i * width + j] = -cost[i * m + j];
        }
        scores[i * width + m + i] = -unmatched;
    }
    match hungarian_max(&scores, n, width) {
        Ok(h) => h
            .row_to_col
            .into_iter()
            .map(|a| a.filter(|&j| j < m))
            .collect(),
        // Only non-finite costs fail, which the costs above never are
        // for finite inputs; no partner is the safe answer.
        Err(_) => vec![None; n],
    }
}

/// Each row's softmax over its robot objects and "no partner"
/// (`exp(-cost)`, normalised): the soft answer, and the share of "no
/// partner" per row.
fn row_shares(cost: &[f64], n: usize, m: usize, unmatched: f64) -> (Vec<f64>, Vec<f64>) {
    let mut soft = vec![0.0; n * m];
    let mut none = vec![0.0; n];
    for i in 0..n {
        let row = &cost[i * m..(i + 1) * m];
        let low = row.iter().copied().fold(unmatched, f64::min);
        let mut z = (low - unmatched).exp();
        for (s, &c) in soft[i * m..(i + 1) * m].iter_mut().zip(row) {
            *s = (low - c).exp();
            z += *s;
        }
        soft[i * m..(i + 1) * m].iter_mut().for_each(|s| *s /= z);
        none[i] = (low - unmatched).exp() / z;
    }
    (soft, none)
}

/// A small deterministic generator (SplitMix64) for the sampler.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn below(&mut self, bound: usize) -> usize {
        (self.next() % bound.max(1) as u64) as usize
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use nalgebra::{Matrix3, Vector3};

    use super::{Rays, SplitMix};

    /// The Sherman-Morrison form against the covariance inverted outright.
    #[test]
    fn ray_distance_is_the_mahalanobis_distance_of_the_ray_covariance() {
        let mut rng = SplitMix(7);
        let mut unit = || (rng.next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        for _ in 0..200 {
            let mut vector = || Vector3::new(unit(), unit(), unit());
            let (r, w, u) = (vector(), vector().normalize(), vector().normalize());
            let (lateral, h, c) = (0.01 + unit().abs(), 4.0 * unit().abs(), 4.0 * unit().abs());
            let rays = Rays {
                human: vec![(w, h)],
                robot_u: [vec![u.x], vec![u.y], vec![u.z]],
                robot_var: vec![c],
                lateral,
            };
            let covariance =
                Matrix3::identity() * lateral + w * w.transpose() * h + u * u.transpose() * c;
            let expected = 0.5 * (r.transpose() * covariance.try_inverse().unwrap() * r)[0];
            let (w_moved, alpha) = rays.human_ray(0, &Matrix3::identity());
            let got = rays.half_distance2([r.x, r.y, r.z], w_moved, alpha, 0);
            assert!(
                (got - expected).abs() <= 1e-9 * expected.max(1.0),
                "{got} against {expected}"
            );
        }
    }

    /// An error along the ray costs what its variance says, one across it
    /// only the lateral scale's: the model that tells look-alikes apart
    /// where depth error is large.
    #[test]
    fn error_along_the_ray_costs_less_than_across_it() {
        let rays = Rays {
            human: vec![(Vector3::z(), 0.0)],
            robot_u: [vec![0.0], vec![0.0], vec![1.0]],
            robot_var: vec![3.0],
            lateral: 1.0,
        };
        let (w, alpha) = rays.human_ray(0, &Matrix3::identity());
        let along = rays.half_distance2([0.0, 0.0, 2.0], w, alpha, 0);
        let across = rays.half_distance2([2.0, 0.0, 0.0], w, alpha, 0);
        assert!((along - 0.5).abs() < 1e-12, "{along}");
        assert!((across - 2.0).abs() < 1e-12, "{across}");
    }
}
