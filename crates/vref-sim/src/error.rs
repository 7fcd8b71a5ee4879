use vref_scene::PairError;

/// A configuration the generator cannot run with. Names the offending
/// field by its path in the configuration, e.g. `classes[2].instances`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConfigError {
    #[error("`{field}`: {message}")]
    Invalid { field: String, message: String },
    #[error("unknown preset {0:?}; known presets: moi, mrc")]
    UnknownPreset(String),
}

/// Why one scene could not be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    #[error(
        "scene {index}: no layout and camera poses in {attempts} attempts let both views see at \
         least {min} objects"
    )]
    NoUsableView {
        index: u64,
        attempts: usize,
        min: usize,
    },
    #[error("scene {index}: generated pair fails validation: {source}")]
    Invalid {
        index: u64,
        #[source]
        source: PairError,
    },
}
