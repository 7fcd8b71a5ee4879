//! Scene graphs: the objects one camera sees, validated, and the dataset
//! files (JSON Lines) that hold pairs of them with ground truth.
//!
//! Everything that enters vref (a dataset line, a shared-memory snapshot, a
//! generated scene) becomes a [`SceneGraph`] through [`SceneGraph::new`],
//! which refuses every defect with a typed [`GraphError`]; the matching code
//! can therefore rely on finite coordinates, unique ids and consistent
//! feature dimensions.

mod dataset;
mod error;
mod graph;
mod limits;
mod pair;

pub use dataset::{DatasetError, DatasetReader, DatasetWriter, read_dataset_file};
pub use error::{GraphError, PairError, Side};
pub use graph::{SceneGraph, SceneObject};
pub use limits::Limits;
pub use pair::ScenePair;
