//! The configuration every vref program reads: `config/vref.toml`.
//!
//! Unknown keys are errors (a misspelt key must not silently fall back to
//! a default), and values are validated when loaded.

mod bridge;
mod ros2;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use vref_match::{MatchError, Params};
use vref_perception::{PerceptionSettings, SegmentationSettings, SettingsError};
use vref_reference::MatcherSettings;
use vref_scene::Limits;
use vref_wire::ipc::IpcSettings;

pub use bridge::{
    BridgeSettings, BridgeSettingsError, EndpointError, PrefixError, StateEncoding, TRANSPORTS,
    ZenohMode, check_endpoint, check_prefix,
};
pub use ros2::{BadDomainId, ROS_DOMAIN_ID_ENV, Ros2Settings};

/// Environment variable naming a configuration file.
pub const CONFIG_ENV: &str = "VREF_CONFIG";
/// Where a program looks when neither `--config` nor the variable is given.
pub const DEFAULT_PATH: &str = "config/vref.toml";
/// Longest `[ipc] prefix`: iceoryx2 names its files and sockets with it.
pub const MAX_IPC_PREFIX: usize = 32;
/// Most bytes of `[ipc] root_path` and `prefix` together: iceoryx2's
/// event sockets live under the root path, and a Unix socket's path has
/// room for 107 bytes (measured with iceoryx2 0.10: 69 works, 71 fails
/// with `ResourceCreationFailed`).
pub const MAX_ROOT_PATH_AND_PREFIX: usize = 69;

/// Why a configuration could not be used.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    #[error("cannot read {path}")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    #[error("{path}: [matching]")]
    Matching {
        path: PathBuf,
        #[source]
        source: MatchError,
    },
    #[error("{path}: [perception]")]
    Perception {
        path: PathBuf,
        #[source]
        source: SettingsError,
    },
    #[error("{path}: [segmentation]")]
    Segmentation {
        path: PathBuf,
        #[source]
        source: SettingsError,
    },
    #[error("{path}: [scene] {message}")]
    Scene { path: PathBuf, message: String },
    #[error("{path}: [bridge]")]
    Bridge {
        path: PathBuf,
        #[source]
        source: BridgeSettingsError,
    },
    #[error("{path}: [{section}] {message}")]
    Section {
        path: PathBuf,
        section: &'static str,
        message: String,
    },
}

/// The whole file.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Config {
    pub scene: SceneConfig,
    pub matching: Params,
    pub matcher: MatcherSettings,
    pub ipc: IpcSettings,
    pub feeds: FeedSettings,
    pub perception: PerceptionSettings,
    pub segmentation: SegmentationSettings,
    pub bridge: BridgeSettings,
    pub ros2: Ros2Settings,
}

/// The `[feeds]` section: how the synthetic feeds publish.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FeedSettings {
    /// Snapshots per second of each view.
    pub snapshot_rate_hz: f64,
    /// Pointing gestures per second.
    pub gesture_rate_hz: f64,
    /// Simulation preset of the synthetic world (moi or mrc).
    pub preset: String,
    /// Seed of the synthetic world; both feeds must use the same.
    pub seed: u64,
    /// Whether the synthetic world's snapshots carry their camera's up
    /// vector (exact: the world's vertical in the camera frame), as a
    /// headset's gravity-aligned frame and a robot's known mounting give.
    pub up_vectors: bool,
}

impl Default for FeedSettings {
    fn default() -> Self {
        Self {
            snapshot_rate_hz: 30.0,
            gesture_rate_hz: 2.0,
            preset: "moi".to_owned(),
            seed: 1,
            up_vectors: true,
        }
    }
}

/// What a valid scene graph may hold.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SceneConfig {
    /// Most objects per view.
    pub capacity: usize,
    /// Largest absolute coordinate accepted, in position units.
    pub max_abs_coordinate: f64,
}

impl Default for SceneConfig {
    fn default() -> Self {
        let limits = Limits::default();
        Self {
            capacity: limits.capacity,
            max_abs_coordinate: limits.max_abs_coordinate,
        }
    }
}

impl SceneConfig {
    pub fn limits(&self) -> Limits {
        Limits {
            capacity: self.capacity,
            max_abs_coordinate: self.max_abs_coordinate,
            require_objects: true,
        }
    }
}

/// Where a configuration came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    File(PathBuf),
    BuiltIn,
}

impl Config {
    /// Parses and validates configuration text; `path` names it in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Self, ConfigError> {
        let config: Config = toml::from_str(text).map_err(|e| ConfigError::Parse {
            path: path.to_owned(),
            message: e.to_string().trim_end().to_owned(),
        })?;
        config.validate(path)?;
        Ok(config)
    }

    /// Reads and validates the file at `path`.
    pub fn from_file(path: &Path) -> Result<Self, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
            path: path.to_owned(),
            source,
        })?;
        Self::parse(&text, path)
    }

    /// The configuration a program runs with: `explicit` (from `--config`)
    /// if given, else the file named by `$VREF_CONFIG`, else
    /// `config/vref.toml` if it exists, else the built-in defaults (which
    /// are the values of the shipped `config/vref.toml`).
    pub fn load(explicit: Option<&Path>) -> Result<(Self, Source), ConfigError> {
        let chosen = explicit
            .map(Path::to_path_buf)
            .or_else(|| std::env::var_os(CONFIG_ENV).map(PathBuf::from))
            .or_else(|| Some(PathBuf::from(DEFAULT_PATH)).filter(|p| p.exists()));
        match chosen {
            Some(path) => Ok((Self::from_file(&path)?, Source::File(path))),
            None => Ok((Self::default(), Source::BuiltIn)),
        }
    }

    fn validate(&self, path: &Path) -> Result<(), ConfigError> {
        self.matching
            .validate()
            .map_err(|source| ConfigError::Matching {
                path: path.to_owned(),
                source,
            })?;
        self.perception
            .validate()
            .map_err(|source| ConfigError::Perception {
                path: path.to_owned(),
                source,
            })?;
        self.segmentation
            .validate()
            .map_err(|source| ConfigError::Segmentation {
                path: path.to_owned(),
                source,
            })?;
        let scene = |message: String| ConfigError::Scene {
            path: path.to_owned(),
            message,
        };
        if self.scene.capacity == 0 {
            return Err(scene("capacity must be at least 1".to_owned()));
        }
        let max = self.scene.max_abs_coordinate;
        if !(max.is_finite() && max > 0.0) {
            return Err(scene(format!(
                "max_abs_coordinate is {max}, but must be positive and finite"
            )));
        }
        self.validate_services(path)
    }

    /// The sections only the services read.
    fn validate_services(&self, path: &Path) -> Result<(), ConfigError> {
        let section = |section: &'static str, message: String| ConfigError::Section {
            path: path.to_owned(),
            section,
            message,
        };
        let matcher = &self.matcher;
        matcher
            .method()
            .map_err(|e| section("matcher", format!("method: {e}")))?;
        matcher
            .tier()
            .map_err(|e| section("matcher", format!("tier: {e}")))?;
        if matcher.stale_after_ms == 0 || matcher.cleanup_interval_ms == 0 {
            return Err(section(
                "matcher",
                "stale_after_ms and cleanup_interval_ms must be at least 1".to_owned(),
            ));
        }
        if matcher.feature_dim_grace_ms == 0 {
            return Err(section(
                "matcher",
                "feature_dim_grace_ms must be at least 1: at 0 two live feeds of different feature lengths would replace each other's snapshots on every message".to_owned(),
            ));
        }
        if matcher.ray_max_age_ms == 0 {
            return Err(section(
                "matcher",
                "ray_max_age_ms must be at least 1".to_owned(),
            ));
        }
        if matcher.max_clock_skew_ms >= matcher.stale_after_ms {
            return Err(section(
                "matcher",
                format!(
                    "max_clock_skew_ms is {}, but must be below stale_after_ms ({}): a clock that far ahead would hide stale answers",
                    matcher.max_clock_skew_ms, matcher.stale_after_ms
                ),
            ));
        }
        if matcher.max_capture_age_ms <= matcher.max_clock_skew_ms {
            return Err(section(
                "matcher",
                format!(
                    "max_capture_age_ms is {}, but must be above max_clock_skew_ms ({})",
                    matcher.max_capture_age_ms, matcher.max_clock_skew_ms
                ),
            ));
        }
        let rate = matcher.max_queries_per_client_hz;
        if !(rate.is_finite() && rate >= 1.0) {
            return Err(section(
                "matcher",
                format!("max_queries_per_client_hz is {rate}, but must be at least 1"),
            ));
        }
        if !(0..=19).contains(&matcher.solver_nice) {
            return Err(section(
                "matcher",
                format!(
                    "solver_nice is {}, but must be in 0..=19",
                    matcher.solver_nice
                ),
            ));
        }
        vref_reference::check_budget(matcher, self.scene.capacity)
            .map_err(|e| section("matcher", e.to_string()))?;
        if matcher.fit_limit.is_nan() || matcher.fit_limit <= 0.0 {
            return Err(section(
                "matcher",
                format!(
                    "fit_limit is {}, but must be positive (inf: no test)",
                    matcher.fit_limit
                ),
            ));
        }
        if !(0.0..=1.0).contains(&matcher.ambiguity_threshold) {
            return Err(section(
                "matcher",
                format!(
                    "ambiguity_threshold is {}, but must be in [0, 1]",
                    matcher.ambiguity_threshold
                ),
            ));
        }
        let ipc = &self.ipc;
        if ipc.namespace.is_empty() || ipc.prefix.is_empty() {
            return Err(section(
                "ipc",
                "namespace and prefix must not be empty".to_owned(),
            ));
        }
        check_ipc_prefix(&ipc.prefix)
            .map_err(|e| section("ipc", format!("prefix `{}`: {e}", ipc.prefix)))?;
        if let Some(root) = &ipc.root_path {
            check_root_path(root, &ipc.prefix)
                .map_err(|e| section("ipc", format!("root_path `{}`: {e}", root.display())))?;
        }
        if ipc.initial_objects == 0 || ipc.max_clients == 0 || ipc.max_subscribers == 0 {
            return Err(section(
                "ipc",
                "initial_objects, max_clients and max_subscribers must be at least 1".to_owned(),
            ));
        }
        let feeds = &self.feeds;
        feeds
            .preset
            .parse::<vref_sim::Preset>()
            .map_err(|e| section("feeds", format!("preset: {e}")))?;
        for (name, rate) in [
            ("snapshot_rate_hz", feeds.snapshot_rate_hz),
            ("gesture_rate_hz", feeds.gesture_rate_hz),
        ] {
            if !(rate.is_finite() && rate > 0.0 && rate <= 10_000.0) {
                return Err(section(
                    "feeds",
                    format!("{name} is {rate}, but must be in (0, 10000]"),
                ));
            }
        }
        self.bridge.check().map_err(|source| ConfigError::Bridge {
            path: path.to_owned(),
            source,
        })?;
        self.ros2
            .check()
            .map_err(|message| section("ros2", message))
    }
}

/// An iceoryx2 file prefix: part of a file name, so no `/`.
fn check_ipc_prefix(prefix: &str) -> Result<(), String> {
    if prefix.len() > MAX_IPC_PREFIX {
        return Err(format!("{} bytes, at most {MAX_IPC_PREFIX}", prefix.len()));
    }
    match prefix
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.')))
    {
        Some(c) => Err(format!(
            "`{c}` is not allowed (letters, digits, `-`, `_` and `.` only: it starts file names)"
        )),
        None => Ok(()),
    }
}

/// An iceoryx2 root path: absolute (a relative one would put iceoryx2's
/// files wherever each program was started), and short enough for its
/// sockets.
fn check_root_path(root: &Path, prefix: &str) -> Result<(), String> {
    if !root.is_absolute() {
        return Err(
            "must be absolute (a relative path is taken from each program's working directory)"
                .to_owned(),
        );
    }
    let len = root.as_os_str().len() + prefix.len();
    if len > MAX_ROOT_PATH_AND_PREFIX {
        return Err(format!(
            "with the prefix {len} bytes, at most {MAX_ROOT_PATH_AND_PREFIX}: iceoryx2's sockets under it would not fit a Unix socket path"
        ));
    }
    Ok(())
}
