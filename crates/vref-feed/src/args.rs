use std::path::PathBuf;
use std::str::FromStr;
use std::time::Duration;

use vref_perception::NoiseSource;

use crate::SetupError;

/// The command line both feeds share.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct FeedArgs {
    /// Configuration file (default: $VREF_CONFIG, else config/vref.toml
    /// if present, else built-in defaults).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// What to publish: `synthetic` (a live world from the [feeds] preset
    /// and seed), `dataset:FILE` (the scene pairs of a JSON Lines dataset
    /// in turn, each for --hold), `recording:FILE` (a vref
    /// recording, MCAP or .vrec, replayed with its own timing, looping), `bop:DIR` (the
    /// scenes of a BOP dataset folder, or of a folder of them, measured by
    /// the perception front end: image 0 is the robot's view, image 1 the
    /// headset's; each scene for --hold, the person pointing at
    /// one object both views measured, another every half scene) or
    /// `rgbd:DIR` (a folder of RGB-D frame folders, or one: rgb.png,
    /// depth.png, optional masks.png, the nearest camera.json; each frame
    /// for --hold, in natural order, segmented where it has no masks; no
    /// pointing rays; docs/perception.md) or `rosbag:FILE.mcap` (a rosbag2
    /// MCAP file with the [ros2] camera topics, measured as vref-ros2
    /// would, replayed with the bag's timing, looping; no pointing rays;
    /// docs/ros2.md).
    #[arg(long, value_name = "SOURCE", default_value = "synthetic")]
    pub source: SourceSpec,
    /// Snapshots per second (default: [feeds] snapshot_rate_hz).
    #[arg(long, value_name = "HZ", allow_negative_numbers = true)]
    pub rate: Option<f64>,
    /// Synthetic source: objects in the world (default: drawn per class as
    /// the preset says). More than the preset ever draws enlarges the
    /// workspace and moves the cameras back to keep the preset's density
    /// and view angles. Both feeds must be given the same.
    #[arg(long, value_name = "N")]
    pub objects: Option<usize>,
    /// Synthetic, dataset, BOP and RGB-D sources: the time origin of the world and of
    /// the scene cycle, nanoseconds since the Unix epoch. Both feeds must
    /// be given the same.
    #[arg(long, value_name = "NS", default_value_t = 0)]
    pub epoch_ns: u64,
    /// Dataset, BOP and RGB-D sources: how long each scene pair is shown, e.g.
    /// 5s, 500ms.
    #[arg(long, value_name = "D", default_value = "5s", value_parser = vref_measure::parse_duration)]
    pub hold: Duration,
    /// BOP source: which way is up (against gravity) in the datasets'
    /// world frame, e.g. 0,0,1; each snapshot then carries its camera's up
    /// vector from the camera's pose (BOP does not say which way its
    /// worlds stand; the rendered scenes of ../shared/data/bop stand on
    /// z). Default: none.
    #[arg(long, value_name = "X,Y,Z", value_parser = vref_measure::parse_direction)]
    pub world_up: Option<[f64; 3]>,
    /// RGB-D and rosbag sources: each camera's per-reading depth noise,
    /// which sets the segmenter's thresholds and the objects' stated
    /// errors: `frame` measures it on each frame (rgbd:) or on the
    /// camera's first frame with enough depth (rosbag:, as vref-ros2),
    /// the configured law where a frame shows too little depth; `config` takes
    /// [perception.robot] or [perception.human] `pixel` (the rendered BOP
    /// cameras by default). Default: frame for rgbd:, [ros2] depth_noise
    /// for rosbag:.
    #[arg(long, value_name = "frame|config")]
    pub noise: Option<NoiseSource>,
    /// The former spelling of --hold, in seconds.
    #[arg(
        long,
        value_name = "SECONDS",
        hide = true,
        conflicts_with = "hold",
        allow_negative_numbers = true
    )]
    pub hold_s: Option<f64>,
}

impl FeedArgs {
    /// The command line's defaults with `source`: what a feed started with
    /// only `--source` would run.
    pub fn with_source(source: SourceSpec) -> Self {
        Self {
            config: None,
            source,
            rate: None,
            objects: None,
            epoch_ns: 0,
            hold: Duration::from_secs(5),
            hold_s: None,
            world_up: None,
            noise: None,
        }
    }

    /// Seconds each scene pair is shown: --hold, or the hidden --hold-s
    /// if that was given.
    pub fn hold_seconds(&self) -> f64 {
        self.hold_s.unwrap_or(self.hold.as_secs_f64())
    }

    /// The flag the hold came from, for messages.
    pub fn hold_flag(&self) -> &'static str {
        if self.hold_s.is_some() {
            "--hold-s"
        } else {
            "--hold"
        }
    }
}

/// Where a feed's content comes from (`--source`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SourceSpec {
    Synthetic,
    Dataset(PathBuf),
    Recording(PathBuf),
    Bop(PathBuf),
    Rgbd(PathBuf),
    Rosbag(PathBuf),
}

/// As `--source` is written: `synthetic`, `bop:DIR`, ...
impl std::fmt::Display for SourceSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (kind, path) = match self {
            SourceSpec::Synthetic => return f.write_str("synthetic"),
            SourceSpec::Dataset(p) => ("dataset", p),
            SourceSpec::Recording(p) => ("recording", p),
            SourceSpec::Bop(p) => ("bop", p),
            SourceSpec::Rgbd(p) => ("rgbd", p),
            SourceSpec::Rosbag(p) => ("rosbag", p),
        };
        write!(f, "{kind}:{}", path.display())
    }
}

impl FromStr for SourceSpec {
    type Err = SetupError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s == "synthetic" {
            return Ok(SourceSpec::Synthetic);
        }
        let (kind, file) = s
            .split_once(':')
            .ok_or_else(|| SetupError::UnknownSource(s.to_owned()))?;
        if file.is_empty() {
            return Err(SetupError::NoFile(s.to_owned()));
        }
        match kind {
            "dataset" => Ok(SourceSpec::Dataset(PathBuf::from(file))),
            "recording" => Ok(SourceSpec::Recording(PathBuf::from(file))),
            "bop" => Ok(SourceSpec::Bop(PathBuf::from(file))),
            "rgbd" => Ok(SourceSpec::Rgbd(PathBuf::from(file))),
            "rosbag" => Ok(SourceSpec::Rosbag(PathBuf::from(file))),
            _ => Err(SetupError::UnknownSource(s.to_owned())),
        }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Command {
        #[command(flatten)]
        args: FeedArgs,
    }

    #[test]
    fn with_source_is_what_the_command_line_gives_by_default() {
        let parsed = Command::try_parse_from(["feed", "--source", "bop:a/b"]).unwrap();
        assert_eq!(
            parsed.args,
            FeedArgs::with_source(SourceSpec::Bop(PathBuf::from("a/b")))
        );
    }

    #[test]
    fn a_source_prints_as_it_is_written() {
        for text in [
            "synthetic",
            "dataset:a.jsonl",
            "bop:a/b",
            "rgbd:f",
            "rosbag:x.mcap",
        ] {
            assert_eq!(text.parse::<SourceSpec>().unwrap().to_string(), text);
        }
    }
}
