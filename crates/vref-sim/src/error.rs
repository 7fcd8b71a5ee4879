use vref_scene::{GraphError, PairError};

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

/// Why a noise sweep could not run. Levels are reported as given, so that
/// a message names the factor the user wrote.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SweepError {
    #[error("unknown sweep {0:?}; known sweeps: depth-noise, feature-noise")]
    UnknownSweep(String),
    #[error("no noise levels to sweep")]
    NoLevels,
    #[error("level {index} is {value}; a level is a factor on the noise, finite and >= 0")]
    BadLevel { index: usize, value: f64 },
    #[error("the scene count per level must be at least 1")]
    NoScenes,
    #[error("no methods to evaluate")]
    NoMethods,
    #[error("matching parameters")]
    Params(#[source] vref_match::MatchError),
    #[error("configuration at noise level {level}")]
    Config {
        level: f64,
        #[source]
        source: ConfigError,
    },
    #[error("generating a scene at noise level {level}")]
    Scene {
        level: f64,
        #[source]
        source: SceneError,
    },
    #[error("matching scene {scene:?} at noise level {level}")]
    Match {
        level: f64,
        scene: String,
        #[source]
        source: vref_match::MatchError,
    },
}

/// Why a rigid scene (the solver benchmark's) could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RigidSceneError {
    #[error("a benchmark scene needs at least 2 objects, got {0}")]
    TooFewObjects(usize),
    #[error("position noise must be finite and at least 0 metres, got {0}")]
    BadNoise(f64),
    #[error("building a synthetic scene: {0}")]
    Scene(#[from] GraphError),
    #[error("building a synthetic scene pair: {0}")]
    Pair(#[from] PairError),
}
