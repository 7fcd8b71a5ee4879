//! Lens distortion, and images rectified to the pinhole camera of the same
//! intrinsics: everything after it (segmenter, front end) assumes a
//! pinhole, and a real camera's lens bends rays by a few per cent towards
//! its image's edges, so objects there would be placed centimetres off.
//!
//! The models and coefficient orders are ROS's `sensor_msgs/CameraInfo`
//! and OpenCV's: `plumb_bob` (`k1 k2 p1 p2 k3`), `rational_polynomial`
//! (`k1 k2 p1 p2 k3 k4 k5 k6`) and `equidistant` (`k1 k2 k3 k4`, OpenCV's
//! fisheye model; a pinhole image of the same intrinsics keeps its
//! middle, not its wide edges). A rectified image is what ROS's
//! `image_proc` calls `image_rect` for a monocular camera with the
//! intrinsics kept: each pixel takes the reading of the raw pixel its
//! ray falls on, the nearest one (depth is never interpolated across an
//! outline); pixels whose ray leaves the raw image have no reading.

use image::{ImageBuffer, Luma, Pixel, Rgb, RgbImage};

use crate::{DepthPixels, Intrinsics, LabelImage};

/// Why distortion coefficients cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LensError {
    #[error(
        "distortion model {model:?} is not supported (supported: plumb_bob, rational_polynomial, equidistant)"
    )]
    Model { model: String },
    #[error("distortion model {model} takes {expected} coefficients, {found} given")]
    Count {
        model: &'static str,
        expected: &'static str,
        found: usize,
    },
    #[error("distortion coefficient {index} is {value}, but must be finite")]
    Value { index: usize, value: f64 },
    #[error("distortion coefficients given without a model")]
    NoModel,
    #[error("the image is {found:?} pixels, but the lens's map is for {expected:?}")]
    Size {
        expected: (u32, u32),
        found: (u32, u32),
    },
}

/// What a stream's stated distortion is taken for: `rectify` (the images
/// are raw, as ROS's `image_raw` topics are, and are rectified before
/// anything else) or `ignore` (they are rectified already, as
/// `image_rect` topics are, beside the same CameraInfo).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DistortionUse {
    #[default]
    Rectify,
    Ignore,
}

/// How a lens bends rays, in normalised image coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Distortion {
    /// `k1 k2 p1 p2 k3`: radial polynomial and tangential terms.
    PlumbBob([f64; 5]),
    /// `k1 k2 p1 p2 k3 k4 k5 k6`: a radial ratio of polynomials and
    /// tangential terms.
    Rational([f64; 8]),
    /// `k1 k2 k3 k4`: a fisheye's angle from the axis, `theta (1 + k1
    /// theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)` (Kannala-Brandt).
    Equidistant([f64; 4]),
}

impl Distortion {
    /// The distortion of a ROS model name and its coefficients; `None`
    /// where there is none (no coefficients, or all zero for a model
    /// whose zero is the pinhole: not `equidistant`, whose zero is the
    /// ideal fisheye). `plumb_bob` takes 4 or 5 coefficients (`k3` 0 when
    /// missing), `rational_polynomial` 8, `equidistant` 4.
    pub fn new(model: &str, d: &[f64]) -> Result<Option<Self>, LensError> {
        if let Some((index, &value)) = d.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(LensError::Value { index, value });
        }
        if d.iter().all(|&v| v == 0.0) && model != "equidistant" {
            return Ok(None);
        }
        let lens = match model {
            "plumb_bob" => match *d {
                [k1, k2, p1, p2] => Self::PlumbBob([k1, k2, p1, p2, 0.0]),
                [k1, k2, p1, p2, k3] => Self::PlumbBob([k1, k2, p1, p2, k3]),
                _ => {
                    return Err(LensError::Count {
                        model: "plumb_bob",
                        expected: "4 or 5",
                        found: d.len(),
                    });
                }
            },
            "rational_polynomial" => {
                let k: [f64; 8] = d.try_into().map_err(|_| LensError::Count {
                    model: "rational_polynomial",
                    expected: "8",
                    found: d.len(),
                })?;
                Self::Rational(k)
            }
            "equidistant" => {
                let k: [f64; 4] = d.try_into().map_err(|_| LensError::Count {
                    model: "equidistant",
                    expected: "4",
                    found: d.len(),
                })?;
                Self::Equidistant(k)
            }
            "" => return Err(LensError::NoModel),
            other => {
                return Err(LensError::Model {
                    model: other.to_owned(),
                });
            }
        };
        Ok(Some(lens))
    }

    /// Where the lens puts the ray of normalised pinhole coordinates `(x,
    /// y)` (`x = X / Z`, `y = Y / Z`).
    pub fn distort(&self, x: f64, y: f64) -> (f64, f64) {
        let r2 = x * x + y * y;
        if let Self::Equidistant([k1, k2, k3, k4]) = *self {
            let r = r2.sqrt();
            if r == 0.0 {
                return (x, y);
            }
            let theta = r.atan();
            let t2 = theta * theta;
            let bent = theta * (1.0 + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4))));
            return (x * bent / r, y * bent / r);
        }
        let (radial, [p1, p2]) = match *self {
            Self::PlumbBob([k1, k2, p1, p2, k3]) => {
                (1.0 + r2 * (k1 + r2 * (k2 + r2 * k3)), [p1, p2])
            }
            Self::Rational([k1, k2, p1, p2, k3, k4, k5, k6]) => (
                (1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))) / (1.0 + r2 * (k4 + r2 * (k5 + r2 * k6))),
                [p1, p2],
            ),
            Self::Equidistant(_) => (1.0, [0.0, 0.0]),
        };
        (
            x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
            y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y,
        )
    }

    /// The pinhole ray (`x = X / Z`, `y = Y / Z`) the lens puts at
    /// normalised point `(xd, yd)`: [`Distortion::distort`] inverted by
    /// fixed-point iteration, as OpenCV's `undistortPoints` does (exact
    /// to rounding for the few per cent real lenses bend).
    pub fn undistort(&self, xd: f64, yd: f64) -> (f64, f64) {
        let (mut x, mut y) = (xd, yd);
        for _ in 0..50 {
            let (dx, dy) = self.distort(x, y);
            (x, y) = (x + xd - dx, y + yd - dy);
        }
        (x, y)
    }
}

/// Rectifies images of one size from one camera: for each pixel of the
/// pinhole image, the raw pixel its ray falls on (computed once; a frame
/// is then one lookup per pixel).
#[derive(Debug, Clone, PartialEq)]
pub struct Rectifier {
    width: u32,
    height: u32,
    /// Per rectified pixel, row-major: the raw pixel's index, or
    /// `u32::MAX` where the ray leaves the raw image.
    source: Vec<u32>,
}

impl Rectifier {
    /// The map of a `width x height` camera with `intrinsics` and `lens`.
    pub fn new(intrinsics: &Intrinsics, lens: &Distortion, width: u32, height: u32) -> Self {
        let (fx, fy, cx, cy) = (
            intrinsics.fx(),
            intrinsics.fy(),
            intrinsics.cx(),
            intrinsics.cy(),
        );
        let mut source = Vec::with_capacity(width as usize * height as usize);
        for v in 0..height {
            for u in 0..width {
                let (x, y) = ((f64::from(u) - cx) / fx, (f64::from(v) - cy) / fy);
                let (xd, yd) = lens.distort(x, y);
                let (ur, vr) = ((fx * xd + cx).round(), (fy * yd + cy).round());
                let inside =
                    (0.0..f64::from(width)).contains(&ur) && (0.0..f64::from(height)).contains(&vr);
                // Within the image, so both fit in u32 and the index in
                // u32 too (images are at most MAX_IMAGE_PIXELS).
                source.push(if inside {
                    vr as u32 * width + ur as u32
                } else {
                    u32::MAX
                });
            }
        }
        Self {
            width,
            height,
            source,
        }
    }

    /// The image size this map is for.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// A frame's colour, depth and labels (if any) rectified: holes are
    /// black, without a reading, and background.
    pub fn frame(
        &self,
        colour: &RgbImage,
        depth: &DepthPixels,
        labels: Option<&LabelImage>,
    ) -> Result<(RgbImage, DepthPixels, Option<LabelImage>), LensError> {
        Ok((
            self.apply(colour, Rgb([0, 0, 0]))?,
            self.apply(depth, Luma([0]))?,
            labels.map(|l| self.apply(l, Luma([0]))).transpose()?,
        ))
    }

    /// `raw` rectified, pixels whose ray leaves it set to `empty`.
    pub fn apply<P: Pixel>(
        &self,
        raw: &ImageBuffer<P, Vec<P::Subpixel>>,
        empty: P,
    ) -> Result<ImageBuffer<P, Vec<P::Subpixel>>, LensError> {
        if raw.dimensions() != (self.width, self.height) {
            return Err(LensError::Size {
                expected: (self.width, self.height),
                found: raw.dimensions(),
            });
        }
        let channels = usize::from(P::CHANNEL_COUNT);
        let (pixels, empty) = (raw.as_raw(), empty.channels());
        let mut out = Vec::with_capacity(self.source.len() * channels);
        for &from in &self.source {
            // u32::MAX (a hole) lies beyond any image.
            let at = (from as usize).saturating_mul(channels);
            let pixel = pixels.get(at..at.saturating_add(channels));
            out.extend_from_slice(pixel.unwrap_or(empty));
        }
        ImageBuffer::from_raw(self.width, self.height, out).ok_or(LensError::Size {
            expected: (self.width, self.height),
            found: raw.dimensions(),
        })
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    #[test]
    fn models_and_counts_are_checked() {
        assert_eq!(Distortion::new("plumb_bob", &[0.0; 5]), Ok(None));
        assert_eq!(Distortion::new("", &[]), Ok(None));
        assert_eq!(Distortion::new("fov", &[0.0]), Ok(None));
        assert_eq!(
            Distortion::new("equidistant", &[0.0; 4]),
            Ok(Some(Distortion::Equidistant([0.0; 4])))
        );
        assert_eq!(
            Distortion::new("plumb_bob", &[0.1, 0.0, 0.0, 0.0]),
            Ok(Some(Distortion::PlumbBob([0.1, 0.0, 0.0, 0.0, 0.0])))
        );
        assert!(matches!(
            Distortion::new("rational_polynomial", &[0.1; 8]),
            Ok(Some(Distortion::Rational(_)))
        ));
        assert_eq!(
            Distortion::new("plumb_bob", &[0.1; 8])
                .unwrap_err()
                .to_string(),
            "distortion model plumb_bob takes 4 or 5 coefficients, 8 given"
        );
        assert_eq!(
            Distortion::new("rational_polynomial", &[0.1; 5]).unwrap_err(),
            LensError::Count {
                model: "rational_polynomial",
                expected: "8",
                found: 5
            }
        );
        assert_eq!(
            Distortion::new("equidistant", &[0.1; 5])
                .unwrap_err()
                .to_string(),
            "distortion model equidistant takes 4 coefficients, 5 given"
        );
        assert_eq!(
            Distortion::new("fov", &[0.1]).unwrap_err().to_string(),
            "distortion model \"fov\" is not supported (supported: plumb_bob, rational_polynomial, equidistant)"
        );
        assert_eq!(Distortion::new("", &[0.1]).unwrap_err(), LensError::NoModel);
        assert_eq!(
            Distortion::new("plumb_bob", &[0.1, f64::NAN, 0.0, 0.0, 0.0])
                .unwrap_err()
                .to_string(),
            "distortion coefficient 1 is NaN, but must be finite"
        );
    }

    /// The models' terms, against values worked by hand.
    #[test]
    fn distortion_follows_the_models() {
        let radial = Distortion::PlumbBob([0.1, 0.01, 0.0, 0.0, 0.001]);
        // r^2 = 0.25: 1 + 0.025 + 0.000625 + 0.000015625.
        let (x, y) = radial.distort(0.3, 0.4);
        let k = 1.025_640_625;
        assert!((x - 0.3 * k).abs() < 1e-15 && (y - 0.4 * k).abs() < 1e-15);
        let tangential = Distortion::PlumbBob([0.0, 0.0, 0.01, 0.02, 0.0]);
        let (x, y) = tangential.distort(0.3, 0.4);
        // 2 p1 x y + p2 (r^2 + 2 x^2); p1 (r^2 + 2 y^2) + 2 p2 x y.
        assert!((x - (0.3 + 0.0024 + 0.0086)).abs() < 1e-15);
        assert!((y - (0.4 + 0.0057 + 0.0048)).abs() < 1e-15);
        let ratio = Distortion::Rational([0.1, 0.0, 0.0, 0.0, 0.0, 0.05, 0.0, 0.0]);
        let (x, _) = ratio.distort(0.3, 0.4);
        assert!((x - 0.3 * 1.025 / 1.0125).abs() < 1e-15);
        // r = 0.5: theta = atan 0.5, bent to theta (1 + 0.1 theta^2) =
        // 0.4736146 from the axis.
        let fisheye = Distortion::Equidistant([0.1, 0.0, 0.0, 0.0]);
        let (x, y) = fisheye.distort(0.3, 0.4);
        assert!((x - 0.284_168_760_102_261_7).abs() < 1e-15);
        assert!((y - 0.378_891_680_136_348_9).abs() < 1e-15);
        assert_eq!(fisheye.distort(0.0, 0.0), (0.0, 0.0));
    }

    /// Undistorting undoes distorting across a wide lens's image.
    #[test]
    fn undistort_inverts_distort() {
        for lens in [
            Distortion::PlumbBob([-0.12, 0.05, 0.0008, -0.0005, 0.0]),
            Distortion::Equidistant([0.05, -0.01, 0.0, 0.0]),
        ] {
            for (x, y) in [(0.0, 0.0), (0.3, -0.2), (-0.6, 0.45), (0.61, 0.46)] {
                let (xd, yd) = lens.distort(x, y);
                let (ux, uy) = lens.undistort(xd, yd);
                assert!(
                    (ux - x).abs() < 1e-12 && (uy - y).abs() < 1e-12,
                    "{lens:?} {x} {y}"
                );
            }
        }
    }

    /// Each rectified pixel holds the raw pixel its ray falls on; rays
    /// that leave the raw image leave holes; another size is refused.
    #[test]
    fn rectifying_looks_up_where_the_lens_put_each_ray() {
        let intrinsics = Intrinsics::new(50.0, 50.0, 40.0, 30.0).unwrap();
        let lens = Distortion::PlumbBob([0.2, 0.0, 0.0, 0.0, 0.0]);
        let rectifier = Rectifier::new(&intrinsics, &lens, 80, 60);
        let raw = ImageBuffer::from_fn(80, 60, |u, v| Luma([(v * 80 + u) as u16]));
        let rect = rectifier.apply(&raw, Luma([0])).unwrap();
        // The principal point stays; a pixel out along x moves further out.
        assert_eq!(rect.get_pixel(40, 30).0[0], 30 * 80 + 40);
        let (xd, _) = lens.distort(20.0 / 50.0, 0.0);
        let u = (50.0 * xd + 40.0).round() as u16;
        assert_eq!(rect.get_pixel(60, 30).0[0], 30 * 80 + u);
        assert!(u > 60);
        // With k1 positive the corners' rays fall outside the raw image.
        assert_eq!(rect.get_pixel(0, 0).0[0], 0);
        assert_eq!(rect.get_pixel(79, 59).0[0], 0);
        // Absurd coefficients (rays sent to infinity, a denominator through
        // zero) leave holes or odd pixels, never a panic or a wrapped index.
        for lens in [
            Distortion::PlumbBob([1e300, 1e300, 0.0, 0.0, 0.0]),
            Distortion::Rational([0.0, 0.0, 0.0, 0.0, 0.0, -4.0, 0.0, 0.0]),
        ] {
            let rect = Rectifier::new(&intrinsics, &lens, 80, 60)
                .apply(&raw, Luma([0]))
                .unwrap();
            assert_eq!(rect.get_pixel(40, 30).0[0], 30 * 80 + 40);
        }
        let other = ImageBuffer::from_pixel(10, 10, Luma([1u16]));
        assert_eq!(
            rectifier.apply(&other, Luma([0])).unwrap_err(),
            LensError::Size {
                expected: (80, 60),
                found: (10, 10)
            }
        );
    }
}
