//! `vref-gesture-feed`: publishes the AR headset's view, one snapshot per
//! tick, and the person's pointing rays, until SIGINT or SIGTERM.
//!
//! Exit codes: 0 stopped on SIGINT/SIGTERM, 1 failure while running,
//! 2 bad command line, configuration or source.

use std::process::ExitCode;

use clap::Parser;
use vref_feed::{FeedArgs, Role, run_feed_with};
use vref_logging::exit::Failure;

/// The vref gesture feed: publishes what the person's AR headset sees as
/// iceoryx2 snapshots, and where the person points. Logs go to stderr
/// (RUST_LOG, default info).
#[derive(Debug, Parser)]
#[command(
    name = "vref-gesture-feed",
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
        run_feed_with(Role::Gesture, &args.feed, Some(&vref_ros2::bag::FeedBags))
            .map_err(Failure::of),
    )
}
