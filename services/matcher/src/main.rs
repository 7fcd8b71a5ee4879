//! `vref-matcher`: the matcher service. One thread waits on both feeds,
//! the gesture feed and reference requests with one WaitSet: it takes
//! snapshots and rays, answers every query from the latest finished
//! solution, publishes statistics and cleans up dead nodes. A second
//! thread solves the newest pair of snapshots whenever one arrives and
//! publishes each decision (docs/reliability.md).
//!
//! Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running,
//! 2 bad configuration (including one that cannot solve within its
//! freshness budget).

mod priority;
mod reject_log;
mod service;
mod solving;
mod stats;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;

/// The vref matcher: answers "which robot object does the person mean?"
/// over iceoryx2. Logs go to stderr (RUST_LOG, default info).
#[derive(Debug, Parser)]
#[command(name = "vref-matcher", version)]
struct Args {
    /// Configuration file (default: $VREF_CONFIG, else config/vref.toml
    /// if present, else built-in defaults).
    #[arg(long, value_name = "FILE")]
    config: Option<PathBuf>,
}

fn main() -> ExitCode {
    let args = Args::parse();
    vref_logging::init("info");
    let config = match vref_config::Config::load(args.config.as_deref()) {
        Ok((config, source)) => {
            tracing::info!(?source, "configuration");
            config
        }
        Err(e) => {
            tracing::error!("{:#}", anyhow::Error::from(e));
            return ExitCode::from(2);
        }
    };
    match service::run(&config) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            tracing::error!("{e:#}");
            ExitCode::from(1)
        }
    }
}
