//! What the command line needs around vref_harness: where the service
//! binaries are.

use std::path::PathBuf;

use anyhow::Context;
use vref_logging::exit::{Blame, Failure};

/// The folder of this binary, where the service binaries are installed.
pub fn bin_dir() -> Result<PathBuf, Failure> {
    let exe = std::env::current_exe().context("locating vref").runtime()?;
    Ok(exe
        .parent()
        .map_or_else(|| PathBuf::from("."), std::path::Path::to_path_buf))
}

/// This binary, for runs that start `vref` subcommands (the echo server,
/// the viewer).
pub fn vref_exe() -> Result<PathBuf, Failure> {
    std::env::current_exe().context("locating vref").runtime()
}
