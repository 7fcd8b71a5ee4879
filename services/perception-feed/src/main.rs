//! `vref-perception-feed`: publishes the robot camera's view, one snapshot
//! per tick, until SIGINT or SIGTERM.
//!
//! Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running,
//! 2 bad command line, configuration or source.

use std::process::ExitCode;

use clap::Parser;
use tracing_subscriber::EnvFilter;
use vref_feed::{Feed, FeedArgs, Role};
use vref_wire::ipc::ServiceNames;

const ROLE: Role = Role::Perception;

/// The vref perception feed: publishes what the robot's camera sees as
/// iceoryx2 snapshots. Logs go to stderr (RUST_LOG, default info).
#[derive(Debug, Parser)]
#[command(name = "vref-perception-feed", version)]
struct Args {
    #[command(flatten)]
    feed: FeedArgs,
}

fn main() -> ExitCode {
    let args = Args::parse();
    tracing_subscriber::fmt()
        .with_env_filter(
            EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .init();
    let config = match vref_config::Config::load(args.feed.config.as_deref()) {
        Ok((config, source)) => {
            tracing::info!(?source, "configuration");
            config
        }
        Err(e) => {
            tracing::error!("{:#}", anyhow::Error::from(e));
            return ExitCode::from(2);
        }
    };
    let mut feed = match Feed::prepare(ROLE, &args.feed, &config) {
        Ok(feed) => feed,
        Err(e) => {
            tracing::error!("{:#}", anyhow::Error::from(e));
            return ExitCode::from(2);
        }
    };
    let ipc = feed.ipc();
    tracing::info!(
        source = %feed.describe(),
        service = %ServiceNames::new(&ipc.namespace).snapshot(ROLE.side()),
        frame = ROLE.frame_name(),
        root_path = ?ipc.root_path,
        prefix = %ipc.prefix,
        rate_hz = ?feed.rate_hz(),
        "perception feed publishing"
    );
    match feed.run(|_| {}) {
        Ok(published) => {
            tracing::info!(snapshots = published.snapshots, "perception feed stopped");
            ExitCode::SUCCESS
        }
        Err(e) => {
            tracing::error!("{:#}", anyhow::Error::from(e));
            ExitCode::from(1)
        }
    }
}
