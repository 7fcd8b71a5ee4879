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
    #[error("scene {name}")]
    Invalid {
        name: String,
        #[source]
        source: vref_scene::PairError,
    },
}
