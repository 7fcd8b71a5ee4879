//! Which side of the objects' plane the cameras stand on.

use nalgebra::Point3;

use crate::Problem;
use crate::rigid::RigidMotion;

/// Both cameras look at the objects from the same side of the surface
/// they stand on (a table top, a floor). When the robot view's objects lie
/// near a plane with the robot camera clearly off it, a motion that puts
/// the human camera clearly on the other side is a mirror of the scene
/// through that plane, and is refused. A human camera near the plane (a
/// person looking across the table at its height) may be on either side
/// of it: refusing those refused the true motion of the Python example's
/// table scene, whose objects then paired as their mirror image. Says
/// nothing for scenes far from planar or cameras in their plane (image
/// coordinates with z = 0).
pub(super) struct Side {
    /// A point of the plane, its normal towards the robot camera, and how
    /// far off the plane a camera must be to count as clearly off it.
    plane: Option<(Point3<f64>, nalgebra::Vector3<f64>, f64)>,
}

impl Side {
    /// Smallest spread of the objects across the plane, as a share of the
    /// next smallest, below which the scene counts as planar.
    const FLATNESS: f64 = 0.25;

    /// The rule for `problem`'s robot view; none where both views know
    /// which way is up, since their motions then cannot turn the scene
    /// over ([`Problem::fit_motion`]).
    pub(super) fn of(problem: &Problem) -> Self {
        if problem.gravity().is_some() {
            return Self { plane: None };
        }
        Self::of_points(&problem.robot_positions)
    }

    fn of_points(points: &[Point3<f64>]) -> Self {
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
        let clear = 3.0 * mid.sqrt() * Self::FLATNESS;
        if camera.abs() <= clear {
            return none;
        }
        if camera < 0.0 {
            normal = -normal;
        }
        Self {
            plane: Some((Point3::from(c), normal, clear)),
        }
    }

    /// Whether `motion` leaves the human camera (its origin) on the robot
    /// camera's side of the plane, or near the plane.
    pub(super) fn allows(&self, motion: &RigidMotion) -> bool {
        self.plane.is_none_or(|(c, normal, clear)| {
            normal.dot(&(motion.apply(&Point3::origin()) - c)) >= -clear
        })
    }
}
