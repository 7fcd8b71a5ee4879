use std::path::PathBuf;

use vref_wire::ipc::IpcError;

/// Why a feed cannot start with the options, configuration and source it
/// was given (the services exit with code 2).
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    #[error(
        "unknown source {0:?}: expected synthetic, dataset:FILE, recording:FILE, bop:DIR, rgbd:DIR or rosbag:FILE.mcap"
    )]
    UnknownSource(String),
    #[error("source {0:?} names no file")]
    NoFile(String),
    #[error("--world-up applies to bop: sources only, not to --source {0}")]
    WorldUpWithoutBop(String),
    #[error("{what} is {value}, but must be positive and finite")]
    BadNumber { what: &'static str, value: f64 },
    #[error("[feeds] preset")]
    Preset(#[source] vref_sim::ConfigError),
    #[error("synthetic world")]
    World(#[source] vref_sim::ConfigError),
    #[error("dataset {path}")]
    Dataset {
        path: PathBuf,
        #[source]
        source: vref_scene::DatasetError,
    },
    #[error("dataset {path} holds no scene pairs")]
    EmptyDataset { path: PathBuf },
    #[error("BOP data {path}")]
    Bop {
        path: PathBuf,
        #[source]
        source: vref_import::ImportError,
    },
    #[error("BOP data {path}: no scene could be measured")]
    EmptyBop { path: PathBuf },
    #[error("RGB-D frames {path}")]
    Rgbd {
        path: PathBuf,
        #[source]
        source: vref_perception::folder::FolderError,
    },
    #[error("segmenting {path}")]
    Segment {
        path: PathBuf,
        #[source]
        source: vref_perception::SegmentError,
    },
    #[error("measuring {path}")]
    Frame {
        path: PathBuf,
        #[source]
        source: vref_perception::FrameError,
    },
    #[error("cannot open recording {path}")]
    OpenRecording {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("recording {path}")]
    Recording {
        path: PathBuf,
        #[source]
        source: vref_record::RecordError,
    },
    #[error("recording {path} holds no {what}{}", cut_note(.cut))]
    EmptyRecording {
        path: PathBuf,
        what: &'static str,
        /// Where the file stopped, if it was cut short.
        cut: Option<vref_record::Cut>,
    },
    #[error("reading the rosbag")]
    Rosbag {
        path: PathBuf,
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    #[error("rosbag {path}: this program does not read rosbag2 files (the feed services do)")]
    NoBagReader { path: PathBuf },
    #[error("{origin}")]
    Entry {
        origin: String,
        #[source]
        source: EntryError,
    },
}

/// Why an object cannot be written as a wire entry.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EntryError {
    #[error("object {id}: feature of dimension {dim} exceeds the wire maximum of {max}")]
    FeatureTooLong { id: u64, dim: usize, max: usize },
    #[error("snapshot feature dimension {dim} exceeds the wire maximum of {max}")]
    FeatureDimTooLong { dim: usize, max: usize },
}

/// Why a running feed stopped other than on request (exit code 1).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Ipc(#[from] IpcError),
    #[error("converting a snapshot")]
    Entry(#[from] EntryError),
}

fn cut_note(cut: &Option<vref_record::Cut>) -> String {
    cut.as_ref().map(|c| format!(" ({c})")).unwrap_or_default()
}
