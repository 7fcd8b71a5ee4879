//! The log set-up of every vref binary, so that the four of them read
//! RUST_LOG and write to stderr the same way.

use std::io::IsTerminal;

use tracing_subscriber::EnvFilter;

/// Sends tracing events to stderr (stdout belongs to the commands'
/// output), filtered by RUST_LOG, else by `default_filter` (e.g. "info"
/// for a service, "warn" for a command line whose output is a table).
/// Colours only on a terminal, so that log files stay plain text.
pub fn init(default_filter: &str) {
    let filter =
        EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new(default_filter));
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_ansi(std::io::stderr().is_terminal())
        .init();
}
