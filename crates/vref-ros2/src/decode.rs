//! ROS images and camera models to the front end's types, refusing what
//! does not add up before a pixel is read: a message is a claim by
//! another process, and a wrong claim (size, step, encoding) must give a
//! reason, not a panic or a garbled frame.

use image::{ImageBuffer, Luma, RgbImage};
use vref_perception::{
    DepthImage, DepthPixels, Distortion, DistortionUse, FrameError, ImageLimit, Intrinsics,
    LabelImage, LensError,
};

use crate::msg::{CameraInfo, Image};

/// Millimetres: what 16UC1 depth counts, and what 32FC1 metres become.
pub const DEPTH_UNIT_M: f64 = 0.001;

/// Which stream a message came on, for counting and logs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Stream {
    Colour,
    Depth,
    Labels,
    CameraInfo,
}

impl Stream {
    pub const ALL: [Stream; 4] = [
        Stream::Colour,
        Stream::Depth,
        Stream::Labels,
        Stream::CameraInfo,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Stream::Colour => "colour",
            Stream::Depth => "depth",
            Stream::Labels => "labels",
            Stream::CameraInfo => "camera_info",
        }
    }
}

/// Why a message was skipped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DecodeError {
    #[error("encoding {found:?} is not supported for {stream} (supported: {supported})")]
    Encoding {
        stream: &'static str,
        found: String,
        supported: &'static str,
    },
    #[error(
        "the image is {width}x{height}, more than the {max_pixels} pixels allowed ([perception] max_image_pixels)"
    )]
    TooLarge {
        width: u32,
        height: u32,
        max_pixels: u64,
    },
    #[error("the image is {width}x{height}: empty")]
    Empty { width: u32, height: u32 },
    #[error("step {step} is less than width {width} x {bytes_per_pixel} bytes")]
    Step {
        step: u32,
        width: u32,
        bytes_per_pixel: u32,
    },
    #[error("data holds {found} bytes, step {step} x height {height} is {expected}")]
    DataSize {
        found: usize,
        step: u32,
        height: u32,
        expected: u64,
    },
    #[error("camera info: {0}")]
    Intrinsics(#[source] FrameError),
    #[error("camera info: {0}")]
    Lens(#[source] LensError),
    #[error("camera info is for {info_width}x{info_height}, the colour image is {width}x{height}")]
    InfoSize {
        info_width: u32,
        info_height: u32,
        width: u32,
        height: u32,
    },
    #[error("header stamp {sec} s {nanosec} ns is before the Unix epoch or not a time")]
    Stamp { sec: i32, nanosec: u32 },
    #[error("stamp {stamp_ns} ns is older than the last one on this topic ({last_ns} ns)")]
    Backwards { stamp_ns: u64, last_ns: u64 },
}

impl DecodeError {
    /// A short name per kind, for counters.
    pub fn reason(&self) -> &'static str {
        match self {
            DecodeError::Encoding { .. } => "encoding",
            DecodeError::TooLarge { .. } => "too_large",
            DecodeError::Empty { .. } => "empty",
            DecodeError::Step { .. } => "step",
            DecodeError::DataSize { .. } => "data_size",
            DecodeError::Intrinsics(_) => "intrinsics",
            DecodeError::Lens(_) => "distortion",
            DecodeError::InfoSize { .. } => "info_size",
            DecodeError::Stamp { .. } => "stamp",
            DecodeError::Backwards { .. } => "stamp_backwards",
        }
    }
}

/// Checks size (against `[perception] max_image_pixels`), step and data
/// length for `bytes_per_pixel`, and returns the step as a usize: before
/// any buffer is sized from the message's claims.
fn check_layout(
    image: &Image,
    bytes_per_pixel: u32,
    max: ImageLimit,
) -> Result<usize, DecodeError> {
    let (width, height) = (image.width, image.height);
    if !max.allows(width, height) {
        return Err(DecodeError::TooLarge {
            width,
            height,
            max_pixels: max.max_pixels,
        });
    }
    if width == 0 || height == 0 {
        return Err(DecodeError::Empty { width, height });
    }
    if u64::from(image.step) < u64::from(width) * u64::from(bytes_per_pixel) {
        return Err(DecodeError::Step {
            step: image.step,
            width,
            bytes_per_pixel,
        });
    }
    let expected = u64::from(image.step) * u64::from(height);
    if image.data.len() as u64 != expected {
        return Err(DecodeError::DataSize {
            found: image.data.len(),
            step: image.step,
            height,
            expected,
        });
    }
    Ok(image.step as usize)
}

/// The rows of `image`, each cut to `row_bytes` (a step may pad rows).
fn rows(image: &Image, step: usize, row_bytes: usize) -> impl Iterator<Item = &[u8]> {
    image.data.chunks_exact(step).map(move |r| &r[..row_bytes])
}

/// A colour image (rgb8, bgr8, or rgba8 and bgra8 with the alpha dropped,
/// as ZED cameras publish).
pub fn colour(image: &Image, max: ImageLimit) -> Result<RgbImage, DecodeError> {
    let (bgr, bytes) = match image.encoding.as_str() {
        "rgb8" => (false, 3),
        "bgr8" => (true, 3),
        "rgba8" => (false, 4),
        "bgra8" => (true, 4),
        other => {
            return Err(DecodeError::Encoding {
                stream: "colour",
                found: other.to_owned(),
                supported: "rgb8, bgr8, rgba8, bgra8",
            });
        }
    };
    let step = check_layout(image, bytes, max)?;
    let row_bytes = image.width as usize * bytes as usize;
    let mut pixels = Vec::with_capacity(image.width as usize * 3 * image.height as usize);
    for row in rows(image, step, row_bytes) {
        for px in row.chunks_exact(bytes as usize) {
            if bgr {
                pixels.extend_from_slice(&[px[2], px[1], px[0]]);
            } else {
                pixels.extend_from_slice(&px[..3]);
            }
        }
    }
    ImageBuffer::from_raw(image.width, image.height, pixels).ok_or(DecodeError::DataSize {
        found: image.data.len(),
        step: image.step,
        height: image.height,
        expected: u64::from(image.step) * u64::from(image.height),
    })
}

/// 16-bit values of a 16UC1/mono16 image, in either byte order.
fn sixteen_bit(
    image: &Image,
    stream: &'static str,
    max: ImageLimit,
) -> Result<ImageBuffer<Luma<u16>, Vec<u16>>, DecodeError> {
    let step = check_layout(image, 2, max)?;
    let row_bytes = image.width as usize * 2;
    let big = image.is_bigendian != 0;
    let mut values = Vec::with_capacity(image.width as usize * image.height as usize);
    for row in rows(image, step, row_bytes) {
        values.extend(row.chunks_exact(2).map(|b| {
            let b = [b[0], b[1]];
            if big {
                u16::from_be_bytes(b)
            } else {
                u16::from_le_bytes(b)
            }
        }));
    }
    ImageBuffer::from_raw(image.width, image.height, values).ok_or(DecodeError::Encoding {
        stream,
        found: image.encoding.clone(),
        supported: "16UC1, mono16",
    })
}

/// A depth image: 16UC1 (or mono16) in millimetres, or 32FC1 in metres
/// (converted to millimetres; NaN, infinite, negative and out-of-range
/// readings become 0, "no reading", as the front end expects).
pub fn depth(image: &Image, max: ImageLimit) -> Result<DepthImage, DecodeError> {
    let pixels: DepthPixels = match image.encoding.as_str() {
        "16UC1" | "mono16" => sixteen_bit(image, "depth", max)?,
        "32FC1" => {
            let step = check_layout(image, 4, max)?;
            let row_bytes = image.width as usize * 4;
            let big = image.is_bigendian != 0;
            let mut values = Vec::with_capacity(image.width as usize * image.height as usize);
            for row in rows(image, step, row_bytes) {
                values.extend(row.chunks_exact(4).map(|b| {
                    let b = [b[0], b[1], b[2], b[3]];
                    let m = if big {
                        f32::from_be_bytes(b)
                    } else {
                        f32::from_le_bytes(b)
                    };
                    let mm = f64::from(m) / DEPTH_UNIT_M;
                    if mm.is_finite() && mm > 0.0 && mm < f64::from(u16::MAX) {
                        mm.round() as u16
                    } else {
                        0
                    }
                }));
            }
            ImageBuffer::from_raw(image.width, image.height, values).ok_or(
                DecodeError::Encoding {
                    stream: "depth",
                    found: image.encoding.clone(),
                    supported: "16UC1, mono16, 32FC1",
                },
            )?
        }
        other => {
            return Err(DecodeError::Encoding {
                stream: "depth",
                found: other.to_owned(),
                supported: "16UC1, mono16, 32FC1",
            });
        }
    };
    DepthImage::new(pixels, DEPTH_UNIT_M).map_err(DecodeError::Intrinsics)
}

/// An instance label image (16UC1 or mono16, 0 background).
pub fn labels(image: &Image, max: ImageLimit) -> Result<LabelImage, DecodeError> {
    match image.encoding.as_str() {
        "16UC1" | "mono16" => sixteen_bit(image, "labels", max),
        other => Err(DecodeError::Encoding {
            stream: "labels",
            found: other.to_owned(),
            supported: "16UC1, mono16",
        }),
    }
}

/// A CameraInfo's camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraModel {
    /// K's pinhole intrinsics.
    pub intrinsics: Intrinsics,
    /// The lens's distortion (`distortion_model`, `d`), where it states one.
    pub lens: Option<Distortion>,
    /// The image size it states (0 x 0: none), for checking frames.
    pub width: u32,
    pub height: u32,
}

/// The camera of a CameraInfo, refusing zero, negative and non-finite
/// focal lengths and a distortion that cannot be used; with `distortion`
/// `Ignore` (images rectified already) its lens is left out unread.
pub fn camera_model(
    info: &CameraInfo,
    distortion: DistortionUse,
) -> Result<CameraModel, DecodeError> {
    let k = &info.k;
    let intrinsics = Intrinsics::new(k[0], k[4], k[2], k[5]).map_err(DecodeError::Intrinsics)?;
    let lens = match distortion {
        DistortionUse::Rectify => {
            Distortion::new(&info.distortion_model, &info.d).map_err(DecodeError::Lens)?
        }
        DistortionUse::Ignore => None,
    };
    Ok(CameraModel {
        intrinsics,
        lens,
        width: info.width,
        height: info.height,
    })
}

/// The header stamp in nanoseconds since the Unix epoch.
pub fn stamp_ns(stamp: crate::msg::Time) -> Result<u64, DecodeError> {
    if stamp.nanosec >= 1_000_000_000 {
        return Err(DecodeError::Stamp {
            sec: stamp.sec,
            nanosec: stamp.nanosec,
        });
    }
    stamp.to_ns().ok_or(DecodeError::Stamp {
        sec: stamp.sec,
        nanosec: stamp.nanosec,
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
    use super::*;

    const MAX: ImageLimit = ImageLimit {
        max_pixels: vref_perception::MAX_IMAGE_PIXELS,
    };

    fn img(encoding: &str, width: u32, height: u32, step: u32, data: Vec<u8>) -> Image {
        Image {
            encoding: encoding.to_owned(),
            width,
            height,
            step,
            data,
            ..Image::default()
        }
    }

    #[test]
    fn bgr8_becomes_rgb_and_padding_is_skipped() {
        // Two pixels per row, a step of 8 (2 bytes of padding).
        let data = vec![1, 2, 3, 4, 5, 6, 99, 99, 7, 8, 9, 10, 11, 12, 99, 99];
        let c = colour(&img("bgr8", 2, 2, 8, data), MAX).unwrap();
        assert_eq!(c.get_pixel(0, 0).0, [3, 2, 1]);
        assert_eq!(c.get_pixel(1, 1).0, [12, 11, 10]);
    }

    #[test]
    fn rgba8_and_bgra8_lose_their_alpha() {
        // Two pixels per row, a step of 12 (4 bytes of padding).
        let data = vec![1, 2, 3, 4, 5, 6, 7, 8, 99, 99, 99, 99];
        let c = colour(&img("rgba8", 2, 1, 12, data.clone()), MAX).unwrap();
        assert_eq!(c.as_raw(), &vec![1, 2, 3, 5, 6, 7]);
        let c = colour(&img("bgra8", 2, 1, 12, data), MAX).unwrap();
        assert_eq!(c.as_raw(), &vec![3, 2, 1, 7, 6, 5]);
        // A step too short for four bytes a pixel.
        let err = colour(&img("rgba8", 2, 1, 6, vec![0; 6]), MAX).unwrap_err();
        assert_eq!(err.reason(), "step");
    }

    #[test]
    fn unsupported_encoding_is_named() {
        let err = colour(&img("yuv422", 1, 1, 2, vec![0; 2]), MAX).unwrap_err();
        assert_eq!(err.reason(), "encoding");
        assert!(err.to_string().contains("yuv422"));
        let err = depth(&img("8UC1", 1, 1, 1, vec![0]), MAX).unwrap_err();
        assert_eq!(err.reason(), "encoding");
    }

    #[test]
    fn size_and_step_mismatches_are_refused() {
        let short_step = colour(&img("rgb8", 4, 1, 11, vec![0; 11]), MAX).unwrap_err();
        assert!(matches!(short_step, DecodeError::Step { .. }));
        let short_data = colour(&img("rgb8", 4, 2, 12, vec![0; 20]), MAX).unwrap_err();
        assert!(matches!(short_data, DecodeError::DataSize { .. }));
        let long_data = depth(&img("16UC1", 2, 2, 4, vec![0; 9]), MAX).unwrap_err();
        assert!(matches!(long_data, DecodeError::DataSize { .. }));
    }

    #[test]
    fn huge_images_are_refused_before_their_data_is_looked_at() {
        let err = colour(&img("rgb8", 20000, 20000, 60000, vec![0; 3]), MAX).unwrap_err();
        assert!(matches!(err, DecodeError::TooLarge { width: 20000, .. }));
        // A step times height that overflows 32 bits must not wrap.
        let err = depth(&img("16UC1", 4000, 4000, u32::MAX, vec![0; 3]), MAX).unwrap_err();
        assert!(matches!(err, DecodeError::DataSize { .. }));
        // A long thin image of more pixels than the cap, though each side
        // is within 4096: the cap is on pixels, as for files.
        let err = labels(&img("mono16", 65536, 300, 131072, vec![]), MAX).unwrap_err();
        assert!(matches!(err, DecodeError::TooLarge { width: 65536, .. }));
    }

    /// `[perception] max_image_pixels` lowered: an ordinary frame is
    /// refused by every stream, naming its size and the key, before its
    /// (here missing) data is looked at.
    #[test]
    fn a_lowered_cap_refuses_an_ordinary_frame() {
        let settings = vref_perception::PerceptionSettings {
            max_image_pixels: 64 * 48 - 1,
            ..Default::default()
        };
        let tight = settings.image_limit();
        for err in [
            colour(&img("rgb8", 64, 48, 192, vec![]), tight).unwrap_err(),
            depth(&img("16UC1", 64, 48, 128, vec![]), tight).unwrap_err(),
            labels(&img("mono16", 64, 48, 128, vec![]), tight).unwrap_err(),
        ] {
            assert_eq!(
                err,
                DecodeError::TooLarge {
                    width: 64,
                    height: 48,
                    max_pixels: 3071
                }
            );
            let text = err.to_string();
            assert!(
                text.contains("64x48") && text.contains("max_image_pixels"),
                "{text}"
            );
        }
        let roomy = vref_perception::ImageLimit {
            max_pixels: 64 * 48,
        };
        assert!(colour(&img("rgb8", 64, 48, 192, vec![0; 192 * 48]), roomy).is_ok());
    }

    #[test]
    fn depth_in_metres_becomes_millimetres_and_bad_readings_none() {
        let values = [1.234f32, f32::NAN, -1.0, 70.0];
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let d = depth(&img("32FC1", 4, 1, 16, data), MAX).unwrap();
        assert_eq!(d.pixels().as_raw(), &vec![1234, 0, 0, 0]);
        assert_eq!(d.metres_per_unit(), DEPTH_UNIT_M);
    }

    #[test]
    fn sixteen_bit_reads_either_byte_order() {
        let mut le = img("16UC1", 1, 1, 2, 1000u16.to_le_bytes().to_vec());
        assert_eq!(depth(&le, MAX).unwrap().pixels().as_raw(), &vec![1000]);
        le.is_bigendian = 1;
        le.data = 1000u16.to_be_bytes().to_vec();
        assert_eq!(depth(&le, MAX).unwrap().pixels().as_raw(), &vec![1000]);
        let l = labels(&img("mono16", 1, 1, 2, 7u16.to_le_bytes().to_vec()), MAX).unwrap();
        assert_eq!(l.as_raw(), &vec![7]);
    }

    #[test]
    fn camera_info_with_zero_or_nan_focal_length_is_refused() {
        let mut info = CameraInfo {
            k: [525.0, 0.0, 319.5, 0.0, 525.0, 239.5, 0.0, 0.0, 1.0],
            width: 640,
            height: 480,
            ..CameraInfo::default()
        };
        let c = camera_model(&info, DistortionUse::Rectify).unwrap();
        let k = c.intrinsics;
        assert_eq!(
            (k.fx(), k.cy(), c.width, c.height),
            (525.0, 239.5, 640, 480)
        );
        assert_eq!(c.lens, None);
        info.k[0] = 0.0;
        assert_eq!(
            camera_model(&info, DistortionUse::Rectify)
                .unwrap_err()
                .reason(),
            "intrinsics"
        );
        info.k[0] = f64::NAN;
        assert_eq!(
            camera_model(&info, DistortionUse::Rectify)
                .unwrap_err()
                .reason(),
            "intrinsics"
        );
    }

    #[test]
    fn camera_info_states_its_lens_or_is_refused_naming_it() {
        let mut info = CameraInfo {
            k: [525.0, 0.0, 319.5, 0.0, 525.0, 239.5, 0.0, 0.0, 1.0],
            distortion_model: "plumb_bob".to_owned(),
            d: vec![0.0; 5],
            ..CameraInfo::default()
        };
        // What RealSense drivers send for a lens they have corrected.
        assert_eq!(
            camera_model(&info, DistortionUse::Rectify).unwrap().lens,
            None
        );
        info.d = vec![-0.1, 0.02, 0.0, 0.0, 0.0];
        assert_eq!(
            camera_model(&info, DistortionUse::Rectify).unwrap().lens,
            Some(Distortion::PlumbBob([-0.1, 0.02, 0.0, 0.0, 0.0]))
        );
        info.distortion_model = "fov".to_owned();
        let err = camera_model(&info, DistortionUse::Rectify).unwrap_err();
        assert_eq!(err.reason(), "distortion");
        assert!(
            err.to_string().contains("\"fov\" is not supported"),
            "{err}"
        );
        // Images rectified already: the lens is not read.
        assert_eq!(
            camera_model(&info, DistortionUse::Ignore).unwrap().lens,
            None
        );
    }

    #[test]
    fn stamps_before_the_epoch_or_with_too_many_nanoseconds_are_refused() {
        use crate::msg::Time;
        assert_eq!(
            stamp_ns(Time { sec: 2, nanosec: 5 }).unwrap(),
            2_000_000_005
        );
        assert!(
            stamp_ns(Time {
                sec: -1,
                nanosec: 0
            })
            .is_err()
        );
        assert!(
            stamp_ns(Time {
                sec: 1,
                nanosec: 1_000_000_000
            })
            .is_err()
        );
    }
}
