//! The log set-up of every vref binary, so that all of them read
//! RUST_LOG and write to stderr the same way, the one-line form of an
//! error with its causes that log lines and counters carry, and the exit
//! codes every binary gives ([`exit`]).

pub mod exit;

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

/// An error and its causes on one line, `error: cause: cause`, as the
/// binaries print them (anyhow's `{:#}`) and as log lines and counters
/// carry them.
pub fn with_causes(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        text.push_str(": ");
        text.push_str(&cause.to_string());
        source = cause.source();
    }
    text
}

#[cfg(test)]
mod tests {
    #[derive(Debug, thiserror::Error)]
    #[error("outer")]
    struct Outer(#[source] std::io::Error);

    #[test]
    fn every_cause_follows_on_one_line() {
        let e = Outer(std::io::Error::other("inner"));
        assert_eq!(super::with_causes(&e), "outer: inner");
        assert_eq!(super::with_causes(&std::io::Error::other("alone")), "alone");
    }
}
