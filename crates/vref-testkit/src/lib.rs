//! What vref's tests share: where the data sets that vref did not make
//! are (`../shared/data` beside the repository, or `VREF_DATA`), so that
//! no test writes that path itself, and where the service executables
//! are ([`binary`], refused when older than their sources).

mod binaries;

use std::path::PathBuf;

pub use binaries::{binary, repo_root, target_dir};

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

#[cfg(test)]
mod tests {
    use super::*;

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
