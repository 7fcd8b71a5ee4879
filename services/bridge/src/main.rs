//! `vref-bridge`: joins this robot's iceoryx2 services to a Zenoh network.
//! Headset snapshots and rays come in and are published locally as a
//! gesture feed would; remote reference queries are asked of the local
//! matcher; the robot's snapshots, the matcher's statistics and decision
//! go out. Everything from the network is checked as strictly as shared
//! memory is (vref-bridge's intake) and counted when refused. The loop is
//! `vref_bridge::run` (crates/vref-bridge), as the matcher's is in
//! crates/vref-serve.
//!
//! Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running,
//! 2 bad configuration.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use vref_logging::exit::{Blame, Failure};

/// The vref bridge: the headset, remote controllers and monitors reach
/// this robot's matcher over Zenoh, under the `[bridge] prefix` keys
/// (docs/remote.md). Logs go to stderr (RUST_LOG, default info).
#[derive(Debug, Parser)]
#[command(
    name = "vref-bridge",
    version,
    after_help = "Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running, 2 bad configuration."
)]
struct Args {
    /// Configuration file (default: $VREF_CONFIG, else config/vref.toml
    /// if present, else built-in defaults); its [bridge] and [ipc]
    /// sections say what to join.
    #[arg(long, value_name = "FILE")]
    config: Option<PathBuf>,
}

fn main() -> ExitCode {
    let args = Args::parse();
    vref_logging::init("info");
    vref_logging::exit::finish(run(&args))
}

fn run(args: &Args) -> Result<(), Failure> {
    let (config, source) = vref_config::Config::load(args.config.as_deref()).bad_input()?;
    tracing::info!(?source, "configuration");
    vref_bridge::run(&config).map_err(Failure::of)
}
