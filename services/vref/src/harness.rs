//! What the command line needs around vref_harness: where the service
//! binaries are, and which exit code a runner's error means.

use std::path::PathBuf;

use anyhow::Context;
use vref_harness::RunError;

use crate::failure::{Blame, Failure};

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

/// Exit code 2 for the caller's input, 1 for the rest.
pub fn failure(error: RunError) -> Failure {
    if error.is_bad_input() {
        Failure::BadInput(error.into())
    } else {
        Failure::Runtime(error.into())
    }
}
