//! The scene's own noise: the ray model's three scales estimated from the
//! residuals that the best motion leaves on the pairs it explains, with
//! the assumed scales as a prior. Sensors, segmentation and the centroid
//! of what each camera sees differ from one setup to the next; a model
//! whose scales are fixed in advance is too wide on one data set and too
//! narrow on another, and its confidence is then wrong on both.

use nalgebra::{Matrix3, Vector3};

use super::costs::{Costs, Noise, Rays};
use crate::RigidMotion;

/// Lowest estimate of a scale, as a share of its prior: a handful of pairs
/// that happen to agree closely must not make the model certain.
const FLOOR: f64 = 0.1;

/// The scales that best explain the residuals of `pairs` (human, robot)
/// under `motion`, by weighted least squares on the squared residual
/// components, with `prior` counted as `weight` pairs' worth of
/// observations. Per pair, with `u` the robot ray, `w` the human ray moved
/// and `n` normal to both: `E[(r.n)^2] = s^2`, `E[(r.u)^2] = s^2 + c + h
/// (u.w)^2`, `E[(r.w)^2] = s^2 + h + c (u.w)^2`, where `c` and `h` are the
/// two depth variances (multipliers of their shapes). Each equation is
/// weighted by its variance (that of a squared Gaussian), starting from the
/// prior; the residual sum is corrected for the six degrees of freedom the
/// motion took from the pairs it was fitted to.
pub(super) fn estimate(
    costs: &Costs<'_>,
    motion: &RigidMotion,
    pairs: &[(usize, usize)],
    prior: Noise,
    weight: f64,
) -> Option<Noise> {
    let rays = costs.rays.as_ref()?;
    if pairs.len() < 3 {
        return None;
    }
    let problem = costs.problem;
    // (coefficients of (s^2, robot, human), observed square) per equation.
    let mut rows: Vec<(Vector3<f64>, f64)> = Vec::with_capacity(3 * pairs.len());
    for &(i, j) in pairs {
        let r = problem.robot_positions[j] - motion.apply(&problem.human_positions[i]);
        let (u, c) = robot_ray(rays, j);
        let w = motion.rotation * rays.human[i].0;
        let h = rays.human_base[i];
        let uw = u.dot(&w);
        let normal = u.cross(&w);
        if normal.norm() > 0.2 {
            rows.push((
                Vector3::new(1.0, 0.0, 0.0),
                r.dot(&normal.normalize()).powi(2),
            ));
        } else {
            // Rays nearly parallel: both directions across them are lateral.
            let across = r - u * r.dot(&u);
            rows.push((Vector3::new(2.0, 0.0, 0.0), across.norm_squared()));
            rows.push((Vector3::new(1.0, c, h), r.dot(&u).powi(2)));
            continue;
        }
        rows.push((Vector3::new(1.0, c, h * uw * uw), r.dot(&u).powi(2)));
        rows.push((Vector3::new(1.0, c * uw * uw, h), r.dot(&w).powi(2)));
    }
    let dof = rows.iter().map(|(a, _)| a[0]).sum::<f64>();
    let correction = dof / (dof - 6.0).max(1.0);
    let median = |v: &[f64]| {
        let mut v = v.to_vec();
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(0.0)
    };
    let (c_typ, h_typ) = (median(&rays.robot_base), median(&rays.human_base));
    let mut theta = Vector3::new(prior.lateral, prior.robot, prior.human);
    for _ in 0..3 {
        let mut normal = Matrix3::zeros();
        let mut rhs = Vector3::zeros();
        for (a, y) in &rows {
            let expected = a.dot(&theta).max(1e-12);
            let wgt = 1.0 / (expected * expected);
            normal += wgt * a * a.transpose();
            rhs += wgt * a * (y * correction);
        }
        // The prior: `weight` pairs whose squares are the prior's, one
        // equation per scale.
        for (k, (value, scale)) in [
            (prior.lateral, 1.0),
            (prior.robot, c_typ),
            (prior.human, h_typ),
        ]
        .into_iter()
        .enumerate()
        {
            let expected = (value * scale).max(1e-12);
            let wgt = weight / (expected * expected);
            let mut a = Vector3::zeros();
            a[k] = scale;
            normal += wgt * a * a.transpose();
            rhs += wgt * a * (value * scale);
        }
        let next = normal.try_inverse()? * rhs;
        theta = Vector3::new(
            next[0].max(FLOOR * prior.lateral),
            next[1].max(FLOOR * prior.robot),
            next[2].max(FLOOR * prior.human),
        );
    }
    theta.iter().all(|v| v.is_finite()).then(|| Noise {
        lateral: theta[0],
        robot: theta[1],
        human: theta[2],
    })
}

fn robot_ray(rays: &Rays, j: usize) -> (Vector3<f64>, f64) {
    (
        Vector3::new(rays.robot_u[0][j], rays.robot_u[1][j], rays.robot_u[2][j]),
        rays.robot_base[j],
    )
}
