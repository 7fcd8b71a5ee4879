//! `vref-ros2`: joins vref to a ROS 2 system until SIGINT or SIGTERM.
//!
//! Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running,
//! 2 bad command line or configuration.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use vref_config::Config;
use vref_logging::exit::{Blame, Failure};

/// vref on ROS 2: subscribes to the robot camera's Image and CameraInfo
/// topics and publishes robot snapshots to the matcher; publishes its
/// decisions as a MarkerArray, each new ok answer to the latest gesture as
/// a PointStamped, the headset pose as a PoseStamped, and serves the
/// latest answer as a std_srvs/Trigger service. Topics and frame ids:
/// [ros2] of the configuration (docs/ros2.md). The DDS domain is
/// ROS_DOMAIN_ID when set. Logs go to stderr (RUST_LOG, default info).
#[derive(Debug, Parser)]
#[command(
    name = "vref-ros2",
    version,
    after_help = "Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running, 2 bad command line or configuration."
)]
struct Args {
    /// Configuration file (default: $VREF_CONFIG, else config/vref.toml,
    /// else the built-in defaults).
    #[arg(long)]
    config: Option<PathBuf>,
}

fn main() -> ExitCode {
    let args = Args::parse();
    // RustDDS logs every discovery step at info.
    vref_logging::init("info,rustdds=warn,ros2_client=warn");
    vref_logging::exit::finish(run(&args))
}

fn run(args: &Args) -> Result<(), Failure> {
    let (config, source) = Config::load(args.config.as_deref()).bad_input()?;
    tracing::info!(?source, "configuration");
    vref_ros2::run(&config)
        .map(|_| ())
        .map_err(|e| Failure::of(e).context("vref-ros2"))
}
