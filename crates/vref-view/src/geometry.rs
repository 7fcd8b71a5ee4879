//! Rotations as Foxglove wants them (quaternions), from what vref has:
//! row-major matrices and directions.

use foxglove::messages::{Point3, Pose, Quaternion, Vector3};

pub(crate) const IDENTITY: Quaternion = Quaternion {
    x: 0.0,
    y: 0.0,
    z: 0.0,
    w: 1.0,
};

/// The unit quaternion of a rotation matrix given row-major (Shepperd's
/// method: the largest of the four candidates keeps it well conditioned).
/// A matrix that is not a rotation gives the quaternion of its nearest
/// reading, normalised; a zero or non-finite one gives the identity.
pub fn quaternion_of(m: &[f64; 9]) -> Quaternion {
    if m.iter().all(|v| v.abs() < 1e-12) || !m.iter().all(|v| v.is_finite()) {
        return IDENTITY;
    }
    let [m00, m01, m02, m10, m11, m12, m20, m21, m22] = *m;
    let trace = m00 + m11 + m22;
    let (x, y, z, w) = if trace > 0.0 {
        let s = (trace + 1.0).sqrt() * 2.0;
        ((m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s)
    } else if m00 > m11 && m00 > m22 {
        let s = (1.0 + m00 - m11 - m22).sqrt() * 2.0;
        (0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s)
    } else if m11 > m22 {
        let s = (1.0 + m11 - m00 - m22).sqrt() * 2.0;
        ((m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s)
    } else {
        let s = (1.0 + m22 - m00 - m11).sqrt() * 2.0;
        ((m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s)
    };
    normalised(x, y, z, w)
}

fn normalised(x: f64, y: f64, z: f64, w: f64) -> Quaternion {
    let n = (x * x + y * y + z * z + w * w).sqrt();
    if !(n.is_finite() && n > 1e-12) {
        return IDENTITY;
    }
    Quaternion {
        x: x / n,
        y: y / n,
        z: z / n,
        w: w / n,
    }
}

/// The shortest rotation taking unit vector `from` onto the direction of
/// `to` (any length but zero; zero gives the identity).
pub fn rotation_between(from: [f64; 3], to: [f64; 3]) -> Quaternion {
    let Some(to) = unit(to) else {
        return IDENTITY;
    };
    let dot = from[0] * to[0] + from[1] * to[1] + from[2] * to[2];
    if dot < -1.0 + 1e-9 {
        // Opposite: half a turn about any axis perpendicular to `from`.
        let axis = if from[0].abs() < 0.9 {
            cross(from, [1.0, 0.0, 0.0])
        } else {
            cross(from, [0.0, 1.0, 0.0])
        };
        return match unit(axis) {
            Some([x, y, z]) => Quaternion { x, y, z, w: 0.0 },
            None => IDENTITY,
        };
    }
    let [x, y, z] = cross(from, to);
    normalised(x, y, z, 1.0 + dot)
}

/// Rotates `v` by unit quaternion `q`.
pub fn rotate(q: &Quaternion, v: [f64; 3]) -> [f64; 3] {
    let u = [q.x, q.y, q.z];
    let t = cross(u, v).map(|c| 2.0 * c);
    let ut = cross(u, t);
    [
        v[0] + q.w * t[0] + ut[0],
        v[1] + q.w * t[1] + ut[1],
        v[2] + q.w * t[2] + ut[2],
    ]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (n.is_finite() && n > 1e-12).then(|| v.map(|c| c / n))
}

pub(crate) fn vector(v: [f64; 3]) -> Vector3 {
    Vector3 {
        x: v[0],
        y: v[1],
        z: v[2],
    }
}

pub(crate) fn point(v: [f64; 3]) -> Point3 {
    Point3 {
        x: v[0],
        y: v[1],
        z: v[2],
    }
}

pub(crate) fn pose(position: [f64; 3], orientation: Quaternion) -> Pose {
    Pose {
        position: Some(vector(position)),
        orientation: Some(orientation),
    }
}

pub(crate) fn f64s(v: [f32; 3]) -> [f64; 3] {
    v.map(f64::from)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
    }

    /// Maps a vector through a row-major matrix.
    fn apply(m: &[f64; 9], v: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|r| m[3 * r] * v[0] + m[3 * r + 1] * v[1] + m[3 * r + 2] * v[2])
    }

    #[test]
    fn quaternions_of_matrices_rotate_as_the_matrices_do() {
        let c = 0.3f64.cos();
        let s = 0.3f64.sin();
        let cases: [[f64; 9]; 5] = [
            [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            [c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0],
            // Camera optical axes (x right, y down, z forward) into a z-up
            // world (x forward, y left): trace -1, the third branch.
            [0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0],
            // Half turns: the other branches.
            [1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0],
            [-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0],
        ];
        for m in cases {
            let q = quaternion_of(&m);
            for v in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.3, -0.2, 0.9]] {
                assert!(close(rotate(&q, v), apply(&m, v)), "{m:?} on {v:?}");
            }
        }
        assert_eq!(quaternion_of(&[0.0; 9]), IDENTITY);
    }

    #[test]
    fn rotation_between_takes_one_direction_onto_the_other() {
        for to in [
            [0.0, 0.0, 1.0],
            [1.0, 2.0, -3.0],
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
        ] {
            let q = rotation_between([1.0, 0.0, 0.0], to);
            assert!(
                close(rotate(&q, [1.0, 0.0, 0.0]), unit(to).unwrap()),
                "{to:?}"
            );
        }
        assert_eq!(rotation_between([1.0, 0.0, 0.0], [0.0; 3]), IDENTITY);
    }
}
