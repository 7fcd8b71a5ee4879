use std::path::PathBuf;

use vref_scene::{DatasetError, Side};

/// Why a picture could not be drawn or written. A wrapped error is the
/// `source`, not repeated in the message.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(
        "picture size {width}x{height} is outside {min_width}x{min_height} to {max_side}x{max_side}"
    )]
    BadSize {
        width: u32,
        height: u32,
        min_width: u32,
        min_height: u32,
        max_side: u32,
    },
    #[error("predicted pair names {side} object id {id}, which is not in the {side} view")]
    UnknownPredictedId { side: Side, id: u64 },
    #[error("series {series:?}, point {index}: ({x}, {y}) is not a pair of finite numbers")]
    NonFinitePoint {
        series: String,
        index: usize,
        x: f64,
        y: f64,
    },
    #[error("the bundled font could not be loaded")]
    Font,
    /// Plotters failed; its errors are generic over the backend, so they
    /// are boxed.
    #[error("drawing")]
    Draw(#[source] Box<dyn std::error::Error + Send + Sync>),
    #[error("encoding PNG")]
    Encode(#[from] png::EncodingError),
    #[error("writing {path}")]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// Why the scene to draw could not be found in a dataset file.
#[derive(Debug, thiserror::Error)]
pub enum SceneLookupError {
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    #[error("no scene named {name:?} among the {total} scenes of the file{}", examples_text(.examples))]
    UnknownScene {
        name: String,
        total: usize,
        /// The first few scene names of the file, to show what is there.
        examples: Vec<String>,
    },
}

fn examples_text(examples: &[String]) -> String {
    if examples.is_empty() {
        String::new()
    } else {
        format!(" (for example: {})", examples.join(", "))
    }
}
