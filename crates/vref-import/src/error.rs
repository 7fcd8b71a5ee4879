use std::path::PathBuf;

/// Why a data set could not be imported.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    #[error("{path}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}, line {line}: {message}")]
    Parse {
        path: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{path}: expected {expected}, found {found}")]
    Shape {
        path: PathBuf,
        expected: String,
        found: String,
    },
    #[error("{dir}: no frames found (expected label/house1, label/house2, ...)")]
    NoFrames { dir: PathBuf },
    #[error("frame gap {gap} leaves no pair among {frames} frames")]
    GapTooLarge { gap: usize, frames: usize },
    #[error("cannot keep {keep} landmarks: frames have {landmarks} (and at least 1 must be kept)")]
    BadKeep { keep: usize, landmarks: usize },
    #[error("{path}")]
    Json {
        path: PathBuf,
        #[source]
        source: serde_json::Error,
    },
    #[error("{dir}: no scene folders found")]
    NoScenes { dir: PathBuf },
    #[error("{path}: no entry for image {image}")]
    MissingImage { path: PathBuf, image: u32 },
    #[error("{path}, image {image}")]
    Frame {
        path: PathBuf,
        image: u32,
        #[source]
        source: vref_perception::FrameError,
    },
    #[error("{path}, image {image}: segmenting")]
    Segment {
        path: PathBuf,
        image: u32,
        #[source]
        source: vref_perception::SegmentError,
    },
    #[error(transparent)]
    Load(#[from] vref_perception::LoadError),
    #[error(
        "{path} is {}x{} pixels, but the colour image {reference} is {}x{}",
        found.0, found.1, expected.0, expected.1
    )]
    ImageSize {
        path: PathBuf,
        found: (u32, u32),
        reference: PathBuf,
        expected: (u32, u32),
    },
    #[error("scene {name}")]
    Invalid {
        name: String,
        #[source]
        source: vref_scene::PairError,
    },
}
