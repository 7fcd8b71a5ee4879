//! Which side of the objects' plane the cameras stand on.

use nalgebra::Point3;

use crate::Problem;
use crate::RigidMotion;

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
    /// Where one view alone knows which way is up: that view's up, the
    /// height of its lowest object along it, and how far below it the
    /// other camera may stand (see [`Above`]).
    above: Option<Above>,
}

/// One known up vector: a person's head and a robot's camera look at the
/// objects on a table or floor from above them, or at most from their
/// height, never from clearly beneath the lowest of them. A motion that
/// puts the other view's camera there turns the scene over, and is
/// refused. (With both known no motion can turn it over.)
struct Above {
    /// The view that knows its up, whose frame the test is made in.
    known: Known,
    up: nalgebra::Vector3<f64>,
    lowest: f64,
    /// The view's median spacing between nearest neighbours: the camera
    /// may stand this far below its lowest object (a crouching person).
    slack: f64,
}

#[derive(Clone, Copy)]
enum Known {
    Robot,
    Human,
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
            return Self {
                plane: None,
                above: None,
            };
        }
        let above = match (problem.human_up, problem.robot_up) {
            (None, Some(up)) => Above::of(Known::Robot, up, &problem.robot_positions),
            (Some(up), None) => Above::of(Known::Human, up, &problem.human_positions),
            _ => None,
        };
        Self {
            above,
            ..Self::of_points(&problem.robot_positions)
        }
    }

    fn of_points(points: &[Point3<f64>]) -> Self {
        let none = Self {
            plane: None,
            above: None,
        };
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
            above: None,
        }
    }

    /// Whether `motion` leaves the human camera (its origin) on the robot
    /// camera's side of the plane, or near the plane; and, where one view
    /// knows which way is up, the other camera not clearly below the
    /// objects.
    pub(super) fn allows(&self, motion: &RigidMotion) -> bool {
        self.plane.is_none_or(|(c, normal, clear)| {
            normal.dot(&(motion.apply(&Point3::origin()) - c)) >= -clear
        }) && self.above.as_ref().is_none_or(|a| a.allows(motion))
    }
}

impl Above {
    fn of(known: Known, up: nalgebra::Vector3<f64>, points: &[Point3<f64>]) -> Option<Self> {
        let lowest = points
            .iter()
            .map(|p| up.dot(&p.coords))
            .fold(f64::INFINITY, f64::min);
        let slack = crate::median_spacing(points)?;
        (lowest.is_finite() && slack.is_finite()).then_some(Self {
            known,
            up,
            lowest,
            slack,
        })
    }

    /// Whether the other camera, in the known view's frame under
    /// `motion`, stands no more than `slack` below the lowest object.
    fn allows(&self, motion: &RigidMotion) -> bool {
        let camera = match self.known {
            Known::Robot => motion.apply(&Point3::origin()),
            Known::Human => motion.inverse().apply(&Point3::origin()),
        };
        self.up.dot(&camera.coords) >= self.lowest - self.slack
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use nalgebra::{Matrix3, Point3, Vector3};

    use super::{Above, Known};
    use crate::RigidMotion;

    /// Objects on a table 1 m in front of the camera, up = -y (OpenCV).
    fn table() -> Vec<Point3<f64>> {
        (0..6)
            .map(|k| Point3::new(-0.25 + 0.1 * k as f64, 0.3, 0.8 + 0.05 * (k % 3) as f64))
            .collect()
    }

    fn at(translation: [f64; 3]) -> RigidMotion {
        RigidMotion {
            rotation: Matrix3::identity(),
            translation: Vector3::from(translation),
        }
    }

    /// With the robot's up known, the human camera above the table, or at
    /// its height, is allowed; clearly beneath it is not. With the human's
    /// known, the same for the robot camera seen from the human frame.
    #[test]
    fn one_known_up_keeps_the_other_camera_from_beneath_the_objects() {
        let up = Vector3::new(0.0, -1.0, 0.0);
        let robot = Above::of(Known::Robot, up, &table()).unwrap();
        // The human camera 0.5 m above the camera's height, at the table's
        // height (y = 0.3), and 0.5 m below the table (y = 0.8).
        assert!(robot.allows(&at([0.0, -0.5, 0.0])));
        assert!(robot.allows(&at([0.3, 0.3, 1.6])));
        assert!(!robot.allows(&at([0.0, 0.8, 0.5])));
        let human = Above::of(Known::Human, up, &table()).unwrap();
        // The robot camera, in the human frame, at -t: below when t is up.
        assert!(human.allows(&at([0.0, 0.2, 0.0])));
        assert!(!human.allows(&at([0.0, -0.8, 0.0])));
    }
}
