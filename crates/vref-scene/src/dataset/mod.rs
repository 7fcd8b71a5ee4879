//! The dataset file: JSON Lines, one scene pair per line (DESIGN.md).

mod reader;
mod record;
mod writer;

use std::path::PathBuf;

pub use reader::{DatasetReader, read_dataset_file};
pub use writer::DatasetWriter;

use crate::PairError;

/// Why a dataset file could not be read or written. Every variant about
/// content names the 1-based line it was found on.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    #[error("cannot open {path}")]
    Open {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("line {line}: read failed")]
    Io {
        line: usize,
        #[source]
        source: std::io::Error,
    },
    #[error("line {line}: longer than {limit} bytes")]
    LineTooLong { line: usize, limit: usize },
    #[error("line {line}: field `{field}`: {message}")]
    Syntax {
        line: usize,
        /// Path of the offending field, e.g. `robot.objects[3].position`
        /// (`.` when the line as a whole is wrong).
        field: String,
        message: String,
    },
    #[error("line {line} (scene {name:?})")]
    Invalid {
        line: usize,
        name: String,
        #[source]
        source: PairError,
    },
    #[error("writing scene {name:?}")]
    Write {
        name: String,
        #[source]
        source: std::io::Error,
    },
}

impl DatasetError {
    /// The 1-based line the error was found on, if it concerns one.
    pub fn line(&self) -> Option<usize> {
        match self {
            DatasetError::Io { line, .. }
            | DatasetError::LineTooLong { line, .. }
            | DatasetError::Syntax { line, .. }
            | DatasetError::Invalid { line, .. } => Some(*line),
            DatasetError::Open { .. } | DatasetError::Write { .. } => None,
        }
    }
}
