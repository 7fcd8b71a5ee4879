//! Proper rigid motions between the two views, fitted by weighted Kabsch
//! (SVD of the cross-covariance): both cameras see the same rigid scene,
//! so one rotation and translation maps the human view onto the robot's.

use nalgebra::{Matrix3, Point3, Rotation3, Vector3};

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

    /// The motion back: `p = rotation^T (q - translation)`.
    pub fn inverse(&self) -> Self {
        let rotation = self.rotation.transpose();
        Self {
            rotation,
            translation: -(rotation * self.translation),
        }
    }

    /// The least-squares proper rigid motion taking each `from[k]` to
    /// `to[k]` with weight `weights[k]` (Kabsch). A reflection is never
    /// returned: when the best orthogonal fit is a mirror, the sign of its
    /// weakest axis is flipped, so a mirror image keeps a large residual
    /// instead of fitting. `None` when the inputs differ in length, have no
    /// positive total weight or are not finite.
    pub fn fit(from: &[Point3<f64>], to: &[Point3<f64>], weights: &[f64]) -> Option<Self> {
        let (cf, ct) = centroids(from, to, weights)?;
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

    /// The least-squares proper rigid motion taking each `from[k]` to
    /// `to[k]` (weights `weights[k]`) that also takes the unit vector
    /// `up_from` to the unit vector `up_to`: both views know which way is
    /// up, so only a turn about it and a translation are left to fit, and
    /// no motion that turns the scene over can be returned. `None` as
    /// [`Self::fit`].
    pub fn fit_upright(
        from: &[Point3<f64>],
        to: &[Point3<f64>],
        weights: &[f64],
        up_from: &Vector3<f64>,
        up_to: &Vector3<f64>,
    ) -> Option<Self> {
        let (cf, ct) = centroids(from, to, weights)?;
        let level = align(up_from, up_to)?;
        let axis = nalgebra::Unit::new_normalize(*up_to);
        // The turn about `up_to` that best takes the levelled offsets to
        // the targets' offsets, in the plane across it: atan2 of the summed
        // cross and dot products.
        let (mut sin, mut cos) = (0.0, 0.0);
        for ((p, q), &w) in from.iter().zip(to).zip(weights) {
            let w = w.max(0.0);
            let a = level * (p.coords - cf);
            let b = q.coords - ct;
            let a = a - axis.dot(&a) * axis.into_inner();
            let b = b - axis.dot(&b) * axis.into_inner();
            sin += w * axis.dot(&a.cross(&b));
            cos += w * a.dot(&b);
        }
        let turn = nalgebra::Rotation3::from_axis_angle(&axis, sin.atan2(cos));
        let rotation = turn.matrix() * level;
        let translation = ct - rotation * cf;
        (rotation.iter().all(|x| x.is_finite()) && translation.iter().all(|x| x.is_finite()))
            .then_some(Self {
                rotation,
                translation,
            })
    }

    /// Root mean square distance between the moved `from` and `to`.
    // Only the experiments (vref-research) and the tests measure it.
    #[cfg(any(test, feature = "research"))]
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

/// The weighted centroids of `from` and `to` (negative weights count 0);
/// `None` when the inputs differ in length, are empty or have no positive
/// finite total weight.
fn centroids(
    from: &[Point3<f64>],
    to: &[Point3<f64>],
    weights: &[f64],
) -> Option<(Vector3<f64>, Vector3<f64>)> {
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
    Some((cf / total, ct / total))
}

/// The smallest rotation taking unit vector `a` to unit vector `b`; for
/// opposite vectors, a half turn about an axis across them. `None` for
/// vectors that are not finite.
fn align(a: &Vector3<f64>, b: &Vector3<f64>) -> Option<Matrix3<f64>> {
    if !(a.iter().chain(b.iter()).all(|x| x.is_finite())) {
        return None;
    }
    if let Some(r) = Rotation3::rotation_between(a, b) {
        return Some(*r.matrix());
    }
    // Opposite (or zero, which the graphs refuse): any axis across `a`.
    let across = if a.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let axis = nalgebra::Unit::try_new(a.cross(&across), 1e-12)?;
    Some(*Rotation3::from_axis_angle(&axis, std::f64::consts::PI).matrix())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use nalgebra::{Point3, Rotation3, Unit, Vector3};

    use super::RigidMotion;

    fn points() -> Vec<Point3<f64>> {
        vec![
            Point3::new(-0.2, 0.1, 0.8),
            Point3::new(0.0, 0.12, 0.95),
            Point3::new(0.18, 0.08, 0.7),
            Point3::new(0.25, 0.15, 1.05),
            Point3::new(-0.1, 0.14, 1.15),
        ]
    }

    #[test]
    fn an_upright_fit_finds_a_motion_that_keeps_up() {
        let up_h = Vector3::new(0.1, -1.0, 0.2).normalize();
        let rotation =
            Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(0.3, 0.5, -0.8)), 1.1);
        let truth = RigidMotion {
            rotation: *rotation.matrix(),
            translation: Vector3::new(-0.9, 0.02, 1.0),
        };
        let up_r = truth.rotation * up_h;
        let from = points();
        let to: Vec<_> = from.iter().map(|p| truth.apply(p)).collect();
        let w = vec![1.0; from.len()];
        let fit = RigidMotion::fit_upright(&from, &to, &w, &up_h, &up_r).unwrap();
        assert!((fit.rotation - truth.rotation).norm() < 1e-9);
        assert!((fit.translation - truth.translation).norm() < 1e-9);
        // The mirror image of the points (turned over) is fitted only with
        // up kept: a large residual, where Kabsch alone may fit it.
        let mirror = RigidMotion {
            rotation: *Rotation3::from_axis_angle(
                &Unit::new_normalize(up_r.cross(&Vector3::x())),
                std::f64::consts::PI,
            )
            .matrix()
                * truth.rotation,
            translation: truth.translation,
        };
        let flipped: Vec<_> = from.iter().map(|p| mirror.apply(p)).collect();
        let fit = RigidMotion::fit_upright(&from, &flipped, &w, &up_h, &up_r).unwrap();
        assert!(((fit.rotation * up_h) - up_r).norm() < 1e-9);
        assert!(
            fit.rms(&from, &flipped) > 0.05,
            "{}",
            fit.rms(&from, &flipped)
        );
    }

    #[test]
    fn opposite_up_vectors_are_a_half_turn() {
        let up = Vector3::new(0.0, -1.0, 0.0);
        let from = points();
        let fit = RigidMotion::fit_upright(&from, &from, &[1.0; 5], &up, &(-up)).unwrap();
        assert!(((fit.rotation * up) + up).norm() < 1e-9);
        assert!((fit.rotation.determinant() - 1.0).abs() < 1e-9);
    }
}
