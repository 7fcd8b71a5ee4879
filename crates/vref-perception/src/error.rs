use std::path::PathBuf;

/// Why a frame cannot be measured: its parts do not fit together.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FrameError {
    #[error("intrinsics: {name} is {value}, but must be {expected}")]
    BadIntrinsics {
        name: &'static str,
        value: f64,
        expected: &'static str,
    },
    #[error("intrinsics: not a pinhole matrix ({message})")]
    NotPinhole { message: String },
    #[error(
        "depth scale (BOP: depth_scale / 1000) is {value:e} m per unit, but must be positive and put the deepest reading (65535 units) within 1000 m"
    )]
    BadDepthScale { value: f64 },
    #[error("the depth image is {found_width}x{found_height}, the colour image {width}x{height}")]
    DepthSize {
        width: u32,
        height: u32,
        found_width: u32,
        found_height: u32,
    },
    #[error(
        "mask of object {id} is {found_width}x{found_height}, the colour image {width}x{height}"
    )]
    MaskSize {
        id: u64,
        width: u32,
        height: u32,
        found_width: u32,
        found_height: u32,
    },
    #[error("the colour image is empty (0 pixels)")]
    Empty,
}

/// Why an image file could not be read as what it should hold.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("cannot open {path}")]
    Open {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error(
        "{path}: {width}x{height} pixels, more than the {max_pixels} an image may have ([perception] max_image_pixels)"
    )]
    TooLarge {
        path: PathBuf,
        width: u32,
        height: u32,
        max_pixels: u64,
    },
    #[error("{path}: the JPEG is cut off (no end-of-image marker): a partly written file?")]
    Truncated { path: PathBuf },
    #[error("cannot decode {path}")]
    Decode {
        path: PathBuf,
        #[source]
        source: image::ImageError,
    },
    #[error("{path}: a depth image must be 16-bit grey, this one is {found:?}")]
    NotDepth16 {
        path: PathBuf,
        found: image::ColorType,
    },
    #[error("{path}: a mask must be 8-bit grey, this one is {found:?}")]
    NotMask {
        path: PathBuf,
        found: image::ColorType,
    },
    #[error(
        "{path}: a colour image must be RGB (8- or 16-bit, alpha dropped) or 8-bit grey, this one is {found:?}"
    )]
    NotColour {
        path: PathBuf,
        found: image::ColorType,
    },
}

/// Why perception settings are refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SettingsError {
    #[error("{name} is {value}, but must be {expected}")]
    Bad {
        name: &'static str,
        value: f64,
        expected: &'static str,
    },
}
