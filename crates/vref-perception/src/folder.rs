//! RGB-D frames kept as folders, the layout `vref segment`, `vref match`
//! and the feeds' `rgbd:` source read:
//!
//! - a frame folder holds `rgb.png` or `rgb.jpg` (RGB or grey,
//!   [`load_colour`]), `depth.png` (16-bit, registered to the colour
//!   image) and optionally `masks.png` (an instance label image, 8- or
//!   16-bit grey, 0 = background, each other value one object: what `vref
//!   segment` writes);
//! - `camera.json` (`fx`, `fy`, `cx`, `cy`, optional `width` and `height`,
//!   `depth_scale_mm`, millimetres per depth unit, default 1, also read
//!   under BOP's name for it, `depth_scale`; optional `distortion_model`
//!   and `d`, the lens as ROS's CameraInfo states it, [`crate::lens`]) is
//!   the nearest one: in the frame folder, else the folder above, else the
//!   one above that. So a single frame, `DIR/camera.json` beside `DIR/NNNN/`
//!   frame folders, and the OSD layout (`camera.json` beside `learn/`)
//!   all read as they are.
//!
//! OSD's own `label.png` is never read as masks: it is ground truth in
//! OSD's scheme (table and background below 20), not instances.
//!
//! A frame whose camera states a lens distortion is rectified as it is
//! loaded: its images (masks too) become the pinhole images of the same
//! intrinsics, and so are the labels and pixels of what is made of them.
//!
//! Every error names the file and what is wrong with it.

use std::path::{Path, PathBuf};

use image::{DynamicImage, RgbImage};

use crate::load::decode;
use crate::segment::LabelImage;
use crate::{
    DepthImage, FrameError, ImageLimit, Intrinsics, LoadError, Rectifier, load_colour, load_depth,
};

/// The colour image of a frame folder, PNG or else JPEG.
pub const RGB_FILE: &str = "rgb.png";
pub const RGB_JPEG_FILE: &str = "rgb.jpg";
/// The depth image of a frame folder.
pub const DEPTH_FILE: &str = "depth.png";
/// A frame folder's own instance masks, where it has them.
pub const MASKS_FILE: &str = "masks.png";
/// The camera file.
pub const CAMERA_FILE: &str = "camera.json";
/// The keys a camera file's values are read from.
pub const CAMERA_KEYS: &str =
    "fx, fy, cx, cy, width, height, depth_scale_mm (or depth_scale), distortion_model, d";

/// Why a frame folder or camera file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum FolderError {
    #[error("cannot read {path}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: not a camera file ({message})")]
    CameraSyntax { path: PathBuf, message: String },
    #[error("{path}: {name} is {value}, but must be finite and positive")]
    CameraValue {
        path: PathBuf,
        name: &'static str,
        value: f64,
    },
    #[error("{path}: bad intrinsics")]
    Intrinsics {
        path: PathBuf,
        #[source]
        source: FrameError,
    },
    #[error("{path}: bad lens distortion")]
    Lens {
        path: PathBuf,
        #[source]
        source: crate::LensError,
    },
    #[error(
        "{path}: depth_scale_mm is {mm} but depth_scale (BOP's name for the same) is {bop}: give one"
    )]
    DepthScales { path: PathBuf, mm: f64, bop: f64 },
    #[error("{path}: give both width and height, or neither")]
    HalfSize { path: PathBuf },
    #[error("no camera file for {frame}: none of {tried} exists")]
    NoCamera { frame: PathBuf, tried: String },
    #[error("{dir}: no frame folders (FRAME/{RGB_FILE} with FRAME/{DEPTH_FILE})")]
    NoFrames { dir: PathBuf },
    #[error(transparent)]
    Load(#[from] LoadError),
    #[error("{path} is {found_width}x{found_height}, but {reference} is {width}x{height}")]
    Size {
        path: PathBuf,
        found_width: u32,
        found_height: u32,
        reference: String,
        width: u32,
        height: u32,
    },
    #[error("{path}: every pixel is 0 (no depth reading at all)")]
    NoDepth { path: PathBuf },
    #[error("{path}: masks must be 8- or 16-bit grey labels, this one is {found:?}")]
    NotLabels {
        path: PathBuf,
        found: image::ColorType,
    },
}

/// A camera, its depth unit and the image size it states.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub intrinsics: Intrinsics,
    pub metres_per_unit: f64,
    pub size: Option<(u32, u32)>,
    /// The lens's distortion, where it has one: its frames are rectified
    /// to the pinhole camera of `intrinsics` as they are loaded.
    pub lens: Option<crate::Distortion>,
}

impl Camera {
    /// The `camera.json` that [`Camera::load`] reads back as this camera
    /// (its size where it states one, its lens where it has one).
    pub fn to_json(&self) -> String {
        let k = &self.intrinsics;
        let mut file = serde_json::json!({
            "fx": k.fx(), "fy": k.fy(), "cx": k.cx(), "cy": k.cy(),
            "depth_scale_mm": self.metres_per_unit * 1000.0,
        });
        if let Some((width, height)) = self.size {
            file["width"] = width.into();
            file["height"] = height.into();
        }
        if let Some(lens) = &self.lens {
            let (model, d): (&str, &[f64]) = match lens {
                crate::Distortion::PlumbBob(d) => ("plumb_bob", d),
                crate::Distortion::Rational(d) => ("rational_polynomial", d),
                crate::Distortion::Equidistant(d) => ("equidistant", d),
            };
            file["distortion_model"] = model.into();
            file["d"] = d.into();
        }
        file.to_string()
    }
}

#[derive(Debug, serde::Deserialize)]
struct CameraFile {
    fx: f64,
    fy: f64,
    cx: f64,
    cy: f64,
    width: Option<u32>,
    height: Option<u32>,
    depth_scale_mm: Option<f64>,
    /// BOP's name for `depth_scale_mm` (its `camera.json` and
    /// `scene_camera.json`: millimetres per depth unit).
    depth_scale: Option<f64>,
    #[serde(default)]
    distortion_model: String,
    #[serde(default)]
    d: Vec<f64>,
    /// Keys this file has that are not read, to be told.
    #[serde(flatten)]
    unread: std::collections::BTreeMap<String, serde::de::IgnoredAny>,
}

impl Camera {
    /// Reads a camera file, refusing values a camera cannot have.
    pub fn load(path: &Path) -> Result<Self, FolderError> {
        Self::read(path).map(|(camera, _)| camera)
    }

    /// [`Camera::load`], with the keys of the file that were not read (a
    /// misspelt `depth_scale_mm` would otherwise leave its default
    /// unnoticed): a program says them.
    pub fn read(path: &Path) -> Result<(Self, Vec<String>), FolderError> {
        let text = std::fs::read_to_string(path).map_err(|source| FolderError::Io {
            path: path.to_owned(),
            source,
        })?;
        let file: CameraFile =
            serde_json::from_str(&text).map_err(|e| FolderError::CameraSyntax {
                path: path.to_owned(),
                message: e.to_string(),
            })?;
        let depth_scale_mm = match (file.depth_scale_mm, file.depth_scale) {
            (Some(mm), Some(bop)) if mm != bop => {
                return Err(FolderError::DepthScales {
                    path: path.to_owned(),
                    mm,
                    bop,
                });
            }
            (Some(scale), _) | (None, Some(scale)) => scale,
            (None, None) => 1.0,
        };
        for (name, value) in [
            ("fx", file.fx),
            ("fy", file.fy),
            ("depth_scale_mm", depth_scale_mm),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(FolderError::CameraValue {
                    path: path.to_owned(),
                    name,
                    value,
                });
            }
        }
        let intrinsics = Intrinsics::new(file.fx, file.fy, file.cx, file.cy).map_err(|source| {
            FolderError::Intrinsics {
                path: path.to_owned(),
                source,
            }
        })?;
        let size = match (file.width, file.height) {
            (Some(w), Some(h)) => Some((w, h)),
            (None, None) => None,
            _ => {
                return Err(FolderError::HalfSize {
                    path: path.to_owned(),
                });
            }
        };
        let lens = crate::Distortion::new(&file.distortion_model, &file.d).map_err(|source| {
            FolderError::Lens {
                path: path.to_owned(),
                source,
            }
        })?;
        let camera = Self {
            intrinsics,
            metres_per_unit: depth_scale_mm / 1000.0,
            size,
            lens,
        };
        Ok((camera, file.unread.into_keys().collect()))
    }
}

/// The camera file of a frame folder: the nearest `camera.json` at or
/// above it (at most two folders up).
pub fn camera_file_of(frame: &Path) -> Result<PathBuf, FolderError> {
    let tried: Vec<PathBuf> = [frame.to_owned(), frame.join(".."), frame.join("../..")]
        .iter()
        .map(|dir| dir.join(CAMERA_FILE))
        .collect();
    tried
        .iter()
        .find(|p| p.is_file())
        .cloned()
        .ok_or_else(|| FolderError::NoCamera {
            frame: frame.to_owned(),
            tried: tried
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", "),
        })
}

/// Whether `dir` is a frame folder (it holds a colour and a depth image).
pub fn is_frame_dir(dir: &Path) -> bool {
    colour_file(dir).is_file() && dir.join(DEPTH_FILE).is_file()
}

/// The colour image of frame folder `dir`: rgb.png, else rgb.jpg.
pub fn colour_file(dir: &Path) -> PathBuf {
    let png = dir.join(RGB_FILE);
    let jpeg = dir.join(RGB_JPEG_FILE);
    if !png.is_file() && jpeg.is_file() {
        jpeg
    } else {
        png
    }
}

/// The frames of `dir`: `dir` itself if it is a frame folder, else its
/// frame folders in natural order (learn2 before learn10, 0009 before
/// 0010), each with its name.
pub fn frame_dirs(dir: &Path) -> Result<Vec<(String, PathBuf)>, FolderError> {
    if is_frame_dir(dir) {
        let name = dir
            .file_name()
            .map_or_else(|| "frame".to_owned(), |n| n.to_string_lossy().into_owned());
        return Ok(vec![(name, dir.to_owned())]);
    }
    let io = |source| FolderError::Io {
        path: dir.to_owned(),
        source,
    };
    let mut frames = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let path = entry.map_err(io)?.path();
        if is_frame_dir(&path) {
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            frames.push((name, path));
        }
    }
    if frames.is_empty() {
        return Err(FolderError::NoFrames {
            dir: dir.to_owned(),
        });
    }
    frames.sort_by_cached_key(|(name, _)| natural_key(name));
    Ok(frames)
}

/// A name's text before its trailing number, and the number: sorting by
/// it puts learn2 before learn10.
pub fn natural_key(name: &str) -> (String, u64, String) {
    let digits = name.len() - name.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    let (stem, number) = name.split_at(name.len() - digits);
    (
        stem.to_owned(),
        number.parse().unwrap_or(u64::MAX),
        name.to_owned(),
    )
}

/// One frame folder decoded and checked against itself and its camera,
/// rectified where the camera states a lens distortion.
#[derive(Debug, Clone)]
pub struct RgbdImages {
    pub camera: Camera,
    pub colour: RgbImage,
    pub depth: DepthImage,
    /// The folder's own masks, where it has them.
    pub masks: Option<LabelImage>,
    /// Keys of the camera file that were not read ([`Camera::read`]);
    /// none where the camera was given.
    pub unread_keys: Vec<String>,
}

impl RgbdImages {
    /// Loads the frame folder `dir` with the nearest camera file; every
    /// image larger than `limit` is refused before it is decoded.
    pub fn load(dir: &Path, limit: ImageLimit) -> Result<Self, FolderError> {
        let (camera, unread_keys) = Camera::read(&camera_file_of(dir)?)?;
        let images = Self::load_with(dir, camera, limit)?;
        Ok(Self {
            unread_keys,
            ..images
        })
    }

    /// Loads the frame folder `dir` taken by `camera`.
    pub fn load_with(dir: &Path, camera: Camera, limit: ImageLimit) -> Result<Self, FolderError> {
        let masks = dir.join(MASKS_FILE);
        let masks = masks.is_file().then_some(masks);
        Self::load_files(
            &colour_file(dir),
            &dir.join(DEPTH_FILE),
            masks.as_deref(),
            camera,
            limit,
        )
    }

    /// Loads a frame from its files, wherever they are: the colour and
    /// depth images and, if given, its masks, checked against each other
    /// and the camera.
    pub fn load_files(
        rgb: &Path,
        depth_path: &Path,
        masks_path: Option<&Path>,
        camera: Camera,
        limit: ImageLimit,
    ) -> Result<Self, FolderError> {
        let rgb = rgb.to_owned();
        let depth_path = depth_path.to_owned();
        let colour = load_colour(&rgb, limit)?;
        let pixels = load_depth(&depth_path, limit)?;
        let (width, height) = colour.dimensions();
        let same = |path: &Path, (w, h): (u32, u32)| {
            if (w, h) == (width, height) {
                Ok(())
            } else {
                Err(FolderError::Size {
                    path: path.to_owned(),
                    found_width: w,
                    found_height: h,
                    reference: rgb.display().to_string(),
                    width,
                    height,
                })
            }
        };
        same(&depth_path, pixels.dimensions())?;
        if let Some((w, h)) = camera.size
            && (w, h) != (width, height)
        {
            return Err(FolderError::Size {
                path: rgb.clone(),
                found_width: width,
                found_height: height,
                reference: "the camera file".to_owned(),
                width: w,
                height: h,
            });
        }
        if pixels.as_raw().iter().all(|&d| d == 0) {
            return Err(FolderError::NoDepth { path: depth_path });
        }
        let masks = match masks_path {
            Some(path) => {
                let labels = load_labels(path, limit)?;
                same(path, labels.dimensions())?;
                Some(labels)
            }
            None => None,
        };
        let (colour, pixels, masks) = match &camera.lens {
            Some(lens) => Rectifier::new(&camera.intrinsics, lens, width, height)
                .frame(&colour, &pixels, masks.as_ref())
                .map_err(|source| FolderError::Lens {
                    path: rgb.clone(),
                    source,
                })?,
            None => (colour, pixels, masks),
        };
        let depth = DepthImage::new(pixels, camera.metres_per_unit).map_err(|source| {
            FolderError::Intrinsics {
                path: depth_path.clone(),
                source,
            }
        })?;
        Ok(Self {
            camera,
            colour,
            depth,
            masks,
            unread_keys: Vec::new(),
        })
    }
}

/// An instance label image, 8- or 16-bit grey, refused before decoding
/// when larger than `limit`.
pub fn load_labels(path: &Path, limit: ImageLimit) -> Result<LabelImage, FolderError> {
    match decode(path, limit)? {
        DynamicImage::ImageLuma16(labels) => Ok(labels),
        grey @ DynamicImage::ImageLuma8(_) => Ok(grey.to_luma16_labels()),
        other => Err(FolderError::NotLabels {
            path: path.to_owned(),
            found: other.color(),
        }),
    }
}

/// 8-bit labels widened without `image`'s rescaling (which would turn
/// label 1 into 257).
trait WidenLabels {
    fn to_luma16_labels(&self) -> LabelImage;
}

impl WidenLabels for DynamicImage {
    fn to_luma16_labels(&self) -> LabelImage {
        let grey = self.to_luma8();
        let (w, h) = grey.dimensions();
        LabelImage::from_fn(w, h, |u, v| {
            image::Luma([u16::from(grey.get_pixel(u, v).0[0])])
        })
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    fn read(text: &str) -> Result<(Camera, Vec<String>), FolderError> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(CAMERA_FILE);
        std::fs::write(&path, text).unwrap();
        Camera::read(&path)
    }

    const K: &str = r#""fx": 500, "fy": 500, "cx": 320, "cy": 240"#;

    /// The depth unit is `depth_scale_mm`, or BOP's `depth_scale` (the
    /// same: millimetres per unit); both, differing, is refused; a key
    /// not read is reported, so that a misspelt one is seen.
    #[test]
    fn the_depth_unit_is_read_under_either_name_and_other_keys_are_reported() {
        let unit = |text: &str| read(text).unwrap().0.metres_per_unit;
        assert_eq!(unit(&format!("{{{K}}}")), 0.001);
        assert_eq!(unit(&format!(r#"{{{K}, "depth_scale_mm": 0.1}}"#)), 0.0001);
        assert_eq!(unit(&format!(r#"{{{K}, "depth_scale": 0.1}}"#)), 0.0001);
        let both = format!(r#"{{{K}, "depth_scale": 0.1, "depth_scale_mm": 0.1}}"#);
        assert_eq!(unit(&both), 0.0001);
        let differ = format!(r#"{{{K}, "depth_scale": 0.1, "depth_scale_mm": 1}}"#);
        let err = read(&differ).unwrap_err();
        assert!(
            matches!(
                err,
                FolderError::DepthScales {
                    mm: 1.0,
                    bop: 0.1,
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("camera.json: depth_scale_mm is 1"));
        let (_, unread) =
            read(&format!(r#"{{{K}, "depth_scal_mm": 0.1, "preset": "x"}}"#)).unwrap();
        assert_eq!(unread, ["depth_scal_mm", "preset"]);
        let (_, unread) = read(&format!("{{{K}}}")).unwrap();
        assert!(unread.is_empty());
    }
}
