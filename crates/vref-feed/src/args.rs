use std::path::PathBuf;
use std::str::FromStr;

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
    /// in turn, each for --hold-s seconds), `recording:FILE` (a vref
    /// recording, MCAP or .vrec, replayed with its own timing, looping) or `bop:DIR` (the
    /// scenes of a BOP dataset folder, or of a folder of them, measured by
    /// the perception front end: image 0 is the robot's view, image 1 the
    /// headset's; each scene for --hold-s seconds, the person pointing at
    /// one object both views measured, another every half scene).
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
    /// Synthetic, dataset and BOP sources: the time origin of the world and of
    /// the scene cycle, nanoseconds since the Unix epoch. Both feeds must
    /// be given the same.
    #[arg(long, value_name = "NS", default_value_t = 0)]
    pub epoch_ns: u64,
    /// Dataset and BOP sources: seconds each scene pair is shown.
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = 5.0,
        allow_negative_numbers = true
    )]
    pub hold_s: f64,
}

/// Where a feed's content comes from (`--source`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SourceSpec {
    Synthetic,
    Dataset(PathBuf),
    Recording(PathBuf),
    Bop(PathBuf),
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
            _ => Err(SetupError::UnknownSource(s.to_owned())),
        }
    }
}
