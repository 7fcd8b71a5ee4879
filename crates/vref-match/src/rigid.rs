//! Proper rigid motions between the two views, fitted by weighted Kabsch
//! (SVD of the cross-covariance): both cameras see the same rigid scene,
//! so one rotation and translation maps the human view onto the robot's.

use nalgebra::{Matrix3, Point3, Vector3};

/// `q = rotation * p + translation`, with `det(rotation) = +1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidMotion {
    pub rotation: Matrix3<f64>,
    pub translation: Vector3<f64>,
}

impl RigidMotion {
    pub fn identity() -> Self {
        Self {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    pub fn apply(&self, p: &Point3<f64>) -> Point3<f64> {
        Point3::from(self.rotation * p.coords + self.translation)
    }

    /// The least-squares proper rigid motion taking each `from[k]` to
    /// `to[k]` with weight `weights[k]` (Kabsch). A reflection is never
    /// returned: when the best orthogonal fit is a mirror, the sign of its
    /// weakest axis is flipped, so a mirror image keeps a large residual
    /// instead of fitting. `None` when the inputs differ in length, have no
    /// positive total weight or are not finite.
    pub fn fit(from: &[Point3<f64>], to: &[Point3<f64>], weights: &[f64]) -> Option<Self> {
        if from.len() != to.len() || from.len() != weights.len() || from.is_empty() {
            return None;
        }
        let total: f64 = weights.iter().filter(|w| **w > 0.0).sum();
        if !(total.is_finite() && total > 0.0) {
            return None;
        }
        let mut cf = Vector3::zeros();
        let mut ct = Vector3::zeros();
        for ((p, q), &w) in from.iter().zip(to).zip(weights) {
            let w = w.max(0.0);
            cf += w * p.coords;
            ct += w * q.coords;
        }
        cf /= total;
        ct /= total;
        let mut h = Matrix3::zeros();
        for ((p, q), &w) in from.iter().zip(to).zip(weights) {
            h += w.max(0.0) * (p.coords - cf) * (q.coords - ct).transpose();
        }
        let svd = h.svd(true, true);
        let (u, v_t) = (svd.u?, svd.v_t?);
        let v = v_t.transpose();
        let d = (v * u.transpose()).determinant().signum();
        // nalgebra sorts singular values in decreasing order, so the last
        // axis is the weakest one.
        let correction = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, d));
        let rotation = v * correction * u.transpose();
        let translation = ct - rotation * cf;
        let motion = Self {
            rotation,
            translation,
        };
        (rotation.iter().all(|x| x.is_finite()) && translation.iter().all(|x| x.is_finite()))
            .then_some(motion)
    }

    /// Root mean square distance between the moved `from` and `to`.
    pub fn rms(&self, from: &[Point3<f64>], to: &[Point3<f64>]) -> f64 {
        let k = from.len().min(to.len());
        if k == 0 {
            return 0.0;
        }
        let sum: f64 = from
            .iter()
            .zip(to)
            .map(|(p, q)| (self.apply(p) - q).norm_squared())
            .sum();
        (sum / k as f64).sqrt()
    }
}

/// Median distance from each point to its nearest neighbour (the scale
/// of `rigid`'s residuals is a fraction of the robot view's); `None` below
/// two points or when all coincide.
pub fn median_spacing(points: &[Point3<f64>]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let mut nearest: Vec<f64> = points
        .iter()
        .enumerate()
        .map(|(a, p)| {
            points
                .iter()
                .enumerate()
                .filter(|&(b, _)| b != a)
                .map(|(_, q)| (p - q).norm())
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    nearest.sort_by(f64::total_cmp);
    let median = nearest[nearest.len() / 2];
    (median.is_finite() && median > 0.0).then_some(median)
}
