//! What vref's tests share, so that each thing is done one way:
//!
//! - where the data sets that vref did not make are (`../shared/data`
//!   beside the repository, or `VREF_DATA`): [`data`];
//! - where the service executables are, refused when older than their
//!   sources: [`binary`];
//! - bounded waits on vref-harness's readiness wait: [`eventually`],
//!   [`join_within`], [`exit_within`];
//! - service processes under a root path and prefix of their own, with a
//!   watchdog per test: [`Harness`];
//! - the checks both feed binaries share: [`feed_cli`];
//! - Zenoh on loopback: [`free_port`], [`bridge_session`].
// A test kit fails the test that calls it: by panicking.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod binaries;
pub mod feed_cli;
mod net;
mod processes;
mod wait;
mod watchdog;

use std::path::PathBuf;

pub use binaries::{binary, repo_root, target_dir};
pub use net::{bridge_session, free_port};
pub use processes::Harness;
pub use wait::{eventually, exit_within, join_within};
pub use watchdog::test_limit;

/// The shared data folder: `VREF_DATA` where it is set and not empty,
/// else `../shared/data` beside the repository.
pub fn data_dir() -> PathBuf {
    match std::env::var_os("VREF_DATA") {
        Some(dir) if !dir.is_empty() => PathBuf::from(dir),
        _ => PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data")),
    }
}

/// `relative` (such as `osd/learn`) inside [`data_dir`].
pub fn data(relative: &str) -> PathBuf {
    data_dir().join(relative)
}

/// The physical object of an OSD ground-truth label (`label.png`; the
/// scheme of `osd/PROVENANCE.md`): parts of the k-th object are labelled
/// `10k` to `10k + 9` from 20 on; lower labels (no reading, the table)
/// are no object, 0.
pub fn osd_object(label: u16) -> u16 {
    if label >= 20 { label / 10 } else { 0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn osd_labels_name_their_objects() {
        assert_eq!(
            [0, 5, 19, 20, 29, 30, 47].map(osd_object),
            [0, 0, 0, 2, 2, 3, 4]
        );
    }

    #[test]
    fn the_default_is_beside_the_repository() {
        if std::env::var_os("VREF_DATA").is_some_and(|d| !d.is_empty()) {
            return;
        }
        let dir = data("osd");
        assert!(dir.ends_with("shared/data/osd"), "{}", dir.display());
        let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
        assert!(dir.starts_with(repo.join("..")), "{}", dir.display());
    }
}
