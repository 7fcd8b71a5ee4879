//! Where the tests find the service executables: in the target folder of
//! the test that runs (`target/<profile>/deps/<test>` runs the binaries of
//! `target/<profile>/`), so that a release test runs release binaries
//! and no test needs another package's `CARGO_BIN_EXE_*`.

use std::path::PathBuf;

/// The folder the running test's executables were built into.
pub fn target_dir() -> PathBuf {
    let exe = std::env::current_exe().unwrap_or_else(|e| panic!("the test's own path: {e}"));
    exe.parent()
        .and_then(|deps| deps.parent())
        .map(PathBuf::from)
        .unwrap_or_else(|| panic!("{} is not in target/<profile>/deps", exe.display()))
}

/// The executable `name` (such as `vref-matcher`) in [`target_dir`].
pub fn binary(name: &str) -> PathBuf {
    let path = target_dir().join(name);
    assert!(
        path.exists(),
        "{} is missing: run `cargo build --workspace --bins` (or `cargo test --workspace`)",
        path.display()
    );
    path
}
