use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use vref_match::Method;

/// vref: which object does the person mean? Graph matching of the robot's
/// and the AR headset's views of one workspace.
///
/// Exit codes: 0 success, 1 failure while running, 2 bad input (usage,
/// configuration or data). Logs go to stderr; set RUST_LOG (e.g.
/// RUST_LOG=info) for more.
#[derive(Debug, Parser)]
#[command(name = "vref", version)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Evaluate matching methods on a dataset file (accuracy, precision,
    /// recall, mean solve time).
    Eval(EvalArgs),
    /// Convert a public data set into a vref dataset file.
    #[command(subcommand)]
    Import(ImportCommand),
    /// Work with configuration files.
    #[command(subcommand)]
    Config(ConfigCommand),
}

#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Dataset file (JSON Lines, one scene pair per line).
    #[arg(long, value_name = "FILE.jsonl")]
    pub dataset: PathBuf,
    /// Method to evaluate; repeat for several. Default: all of them
    /// (appearance, sm, rrwm, paper).
    #[arg(long = "method", value_name = "NAME", value_parser = parse_method)]
    pub methods: Vec<Method>,
    /// Spatial bandwidth beta, overriding the configuration (CMU House in
    /// pixels: 2500).
    #[arg(long, value_name = "B", allow_negative_numbers = true)]
    pub beta: Option<f64>,
    /// Print one JSON object per method on stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Configuration file (default: $VREF_CONFIG, else config/vref.toml if
    /// present, else built-in defaults).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Subcommand)]
pub enum ImportCommand {
    /// CMU House landmarks (FGM layout: label/, adj/, scf/): human view =
    /// frame k, robot view = frame k + gap, positions (x, y, 0) in pixels.
    CmuHouse(CmuHouseArgs),
}

#[derive(Debug, Args)]
pub struct CmuHouseArgs {
    /// Directory holding label/, adj/ and scf/.
    pub dir: PathBuf,
    /// Frame gap between the human and the robot view.
    #[arg(long, value_name = "G")]
    pub gap: usize,
    /// Keep only each frame's Delaunay edges (default: fully connected).
    #[arg(long)]
    pub delaunay: bool,
    /// Use the shape contexts as appearance features (default: none).
    #[arg(long)]
    pub features: bool,
    /// Keep K random landmarks per frame, chosen independently per view,
    /// so that some objects have no partner.
    #[arg(long, value_name = "K")]
    pub keep: Option<usize>,
    /// Seed of the landmark choice and of the robot view's object order.
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// Output dataset file (default: stdout).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

#[derive(Debug, Subcommand)]
pub enum ConfigCommand {
    /// Validate a configuration file; exit 2 naming the first problem.
    Check(ConfigCheckArgs),
}

#[derive(Debug, Args)]
pub struct ConfigCheckArgs {
    /// The file to check.
    pub file: PathBuf,
}

fn parse_method(s: &str) -> Result<Method, String> {
    s.parse().map_err(|e: vref_match::MatchError| e.to_string())
}
