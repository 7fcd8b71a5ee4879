//! The pinhole camera: pixels to rays and back (OpenCV conventions: x
//! right, y down, z forward; pixel `(u, v)` is the centre of column `u`,
//! row `v`).

use crate::FrameError;

/// Focal lengths and principal point, in pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Intrinsics {
    fx: f64,
    fy: f64,
    cx: f64,
    cy: f64,
}

impl Intrinsics {
    /// Refuses focal lengths that are not positive and finite and a
    /// principal point that is not finite and non-negative.
    pub fn new(fx: f64, fy: f64, cx: f64, cy: f64) -> Result<Self, FrameError> {
        for (name, value) in [("fx", fx), ("fy", fy)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(FrameError::BadIntrinsics {
                    name,
                    value,
                    expected: "positive and finite",
                });
            }
        }
        for (name, value) in [("cx", cx), ("cy", cy)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(FrameError::BadIntrinsics {
                    name,
                    value,
                    expected: "finite and not negative",
                });
            }
        }
        Ok(Self { fx, fy, cx, cy })
    }

    /// From a row-major 3x3 camera matrix `[fx 0 cx; 0 fy cy; 0 0 1]`, as
    /// BOP's `cam_K` holds it. A skewed or projective matrix is refused.
    pub fn from_matrix(k: &[f64; 9]) -> Result<Self, FrameError> {
        let fixed = [(1, 0.0), (3, 0.0), (6, 0.0), (7, 0.0), (8, 1.0)];
        if let Some(&(index, want)) = fixed.iter().find(|&&(i, want)| k[i] != want) {
            return Err(FrameError::NotPinhole {
                message: format!("entry {index} is {}, expected {want}", k[index]),
            });
        }
        Self::new(k[0], k[4], k[2], k[5])
    }

    pub fn fx(&self) -> f64 {
        self.fx
    }

    pub fn fy(&self) -> f64 {
        self.fy
    }

    pub fn cx(&self) -> f64 {
        self.cx
    }

    pub fn cy(&self) -> f64 {
        self.cy
    }

    /// The point at depth `z` (along the optical axis) seen at pixel
    /// `(u, v)`.
    pub fn back_project(&self, u: f64, v: f64, z: f64) -> [f64; 3] {
        [(u - self.cx) * z / self.fx, (v - self.cy) * z / self.fy, z]
    }

    /// The pixel a point in front of the camera is seen at; `None` for
    /// points at or behind the camera plane.
    pub fn project(&self, p: [f64; 3]) -> Option<[f64; 2]> {
        (p[2] > 0.0).then(|| {
            [
                self.fx * p[0] / p[2] + self.cx,
                self.fy * p[1] / p[2] + self.cy,
            ]
        })
    }
}
