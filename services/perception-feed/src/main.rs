//! `vref-perception-feed`: publishes the robot camera's view, one snapshot
//! per tick, until SIGINT or SIGTERM.
//!
//! Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running,
//! 2 bad command line, configuration or source.

use std::process::ExitCode;

use clap::Parser;
use vref_feed::{FeedArgs, Role, run_feed_with};
use vref_logging::exit::Failure;

/// The vref perception feed: publishes what the robot's camera sees as
/// iceoryx2 snapshots. Logs go to stderr (RUST_LOG, default info).
#[derive(Debug, Parser)]
#[command(
    name = "vref-perception-feed",
    version,
    after_help = "Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running, 2 bad command line, configuration or source."
)]
struct Args {
    #[command(flatten)]
    feed: FeedArgs,
}

fn main() -> ExitCode {
    let args = Args::parse();
    vref_logging::init("info");
    vref_logging::exit::finish(
        run_feed_with(
            Role::Perception,
            &args.feed,
            Some(&vref_ros2::bag::FeedBags),
        )
        .map_err(Failure::of),
    )
}
