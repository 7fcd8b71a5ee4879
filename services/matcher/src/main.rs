//! `vref-matcher`: the matcher service; its loop is `vref_serve::run`
//! (crates/vref-serve), as the feeds' loops are in crates/vref-feed.
//!
//! Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running,
//! 2 bad configuration (including one that cannot solve within its
//! freshness budget).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;

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
    if let Err(e) = vref_match::check_simd_setting() {
        tracing::error!("{e}");
        return ExitCode::from(2);
    }
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
    match vref_serve::run(&config) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let code = if e.is_configuration() { 2 } else { 1 };
            tracing::error!("{:#}", anyhow::Error::from(e));
            ExitCode::from(code)
        }
    }
}
