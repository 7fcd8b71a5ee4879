//! `vref-matcher`: the matcher service; its loop is `vref_serve::run`
//! (crates/vref-serve), as the feeds' loops are in crates/vref-feed.
//!
//! Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running,
//! 2 bad configuration (including one that cannot solve within its
//! freshness budget).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use vref_logging::exit::{Blame, Failure};

/// The vref matcher: answers "which robot object does the person mean?"
/// over iceoryx2. Logs go to stderr (RUST_LOG, default info).
#[derive(Debug, Parser)]
#[command(
    name = "vref-matcher",
    version,
    after_help = "Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running, 2 bad configuration (including one that cannot solve within its freshness budget)."
)]
struct Args {
    /// Configuration file (default: $VREF_CONFIG, else config/vref.toml
    /// if present, else built-in defaults).
    #[arg(long, value_name = "FILE")]
    config: Option<PathBuf>,
}

fn main() -> ExitCode {
    let args = Args::parse();
    vref_logging::init("info");
    vref_logging::exit::finish(run(&args))
}

fn run(args: &Args) -> Result<(), Failure> {
    vref_match::check_simd_setting().bad_input()?;
    let (config, source) = vref_config::Config::load(args.config.as_deref()).bad_input()?;
    tracing::info!(?source, "configuration");
    vref_serve::run(&config).map_err(Failure::of)
}
