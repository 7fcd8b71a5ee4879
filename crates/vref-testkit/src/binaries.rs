//! Where the tests find the service executables: in the target folder of
//! the test that runs (`target/<profile>/deps/<test>` runs the binaries of
//! `target/<profile>/`), so that a release test runs release binaries
//! and no test needs another package's `CARGO_BIN_EXE_*`.
//!
//! `cargo test --workspace` builds every executable before any test runs
//! (each service package has an integration test of its own); `cargo test
//! -p vref-system-tests` alone does not, and would silently run the
//! executables of an older build: a binary older than a source it is
//! built from is refused, naming that source. Its sources are the `src/`
//! files of its package and of the workspace crates its manifests name
//! under `[dependencies]`, followed through their manifests (cargo's own
//! dep-info of a binary, beside it, is only written by `cargo build`, and
//! only a file of those makes cargo relink it).

use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// What to run when an executable is missing or out of date.
const BUILD: &str = "run `cargo build --workspace --bins` (or `cargo test --workspace`)";

/// The folder the running test's executables were built into.
pub fn target_dir() -> PathBuf {
    let exe = std::env::current_exe().unwrap_or_else(|e| panic!("the test's own path: {e}"));
    exe.parent()
        .and_then(|deps| deps.parent())
        .map(PathBuf::from)
        .unwrap_or_else(|| panic!("{} is not in target/<profile>/deps", exe.display()))
}

/// The executable `name` (such as `vref-matcher`) in [`target_dir`],
/// built from the sources as they are now.
pub fn binary(name: &str) -> PathBuf {
    let dir = target_dir();
    let problem = match vref_harness::launch::binary(&dir, name) {
        Ok(path) => match out_of_date(&repo_root(), &path, name) {
            None => return path,
            Some(problem) => problem,
        },
        Err(_) => format!("{} is missing", shown(&dir.join(name))),
    };
    panic!("{problem}: {BUILD}")
}

/// Why the executable `name` at `path`, built from the workspace at
/// `root`, cannot be trusted, if it cannot.
fn out_of_date(root: &Path, path: &Path, name: &str) -> Option<String> {
    let Some(built) = modified(path) else {
        return Some(format!("{} is missing", shown(path)));
    };
    let (at, newest) = sources(root, name)
        .into_iter()
        .filter_map(|source| Some((modified(&source)?, source)))
        .max()?;
    (at > built).then(|| format!("{} is older than {}", shown(path), shown(&newest)))
}

/// One package of the workspace, as its manifest says.
#[derive(Debug)]
struct Package {
    dir: PathBuf,
    name: String,
    bins: Vec<String>,
    dependencies: Vec<String>,
}

/// The packages in `root`'s `crates/` and `services/`.
fn packages(root: &Path) -> Vec<Package> {
    ["crates", "services"]
        .iter()
        .flat_map(|folder| std::fs::read_dir(root.join(folder)).into_iter().flatten())
        .flatten()
        .filter_map(|entry| {
            let dir = entry.path();
            let manifest = std::fs::read_to_string(dir.join("Cargo.toml")).ok()?;
            Some(package(dir, &manifest))
        })
        .collect()
}

/// What a manifest names: the package, its `[[bin]]`s and the packages
/// under `[dependencies]` (`name.workspace = true` or `name = {...}`).
fn package(dir: PathBuf, manifest: &str) -> Package {
    let mut package = Package {
        dir,
        name: String::new(),
        bins: Vec::new(),
        dependencies: Vec::new(),
    };
    let mut section = "";
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            section = line;
            continue;
        }
        let Some((key, value)) = line.split_once('=') else {
            continue;
        };
        let (key, value) = (key.trim(), value.trim().trim_matches('"'));
        match section {
            "[package]" if key == "name" => package.name = value.to_owned(),
            "[[bin]]" if key == "name" => package.bins.push(value.to_owned()),
            "[dependencies]" => {
                let name = key.trim_end_matches(".workspace");
                package.dependencies.push(name.to_owned());
            }
            _ => {}
        }
    }
    package
}

/// The `src/` files of the package of binary `name` and of every
/// workspace package it depends on.
fn sources(root: &Path, name: &str) -> Vec<PathBuf> {
    let packages = packages(root);
    let mut wanted: Vec<&Package> = packages
        .iter()
        .filter(|p| p.bins.iter().any(|b| b == name))
        .collect();
    let mut next = 0;
    while next < wanted.len() {
        let current = wanted[next];
        for name in &current.dependencies {
            let found = packages.iter().find(|p| &p.name == name);
            if let Some(dependency) = found.filter(|d| !wanted.iter().any(|w| w.name == d.name)) {
                wanted.push(dependency);
            }
        }
        next += 1;
    }
    let mut files = Vec::new();
    for p in wanted {
        files_in(&p.dir.join("src"), &mut files);
    }
    files
}

/// Every file under `dir`, into `files`.
fn files_in(dir: &Path, files: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let path = entry.path();
        if path.is_dir() {
            files_in(&path, files);
        } else {
            files.push(path);
        }
    }
}

fn modified(path: &Path) -> Option<SystemTime> {
    path.metadata().and_then(|m| m.modified()).ok()
}

/// The repository (this crate is `crates/vref-testkit`).
pub fn repo_root() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    root.canonicalize().unwrap_or(root)
}

/// `path` inside the repository as from its root, for a message one
/// line long.
fn shown(path: &Path) -> String {
    let root = repo_root();
    path.strip_prefix(&root)
        .unwrap_or(path)
        .display()
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(path: &Path, text: &str) {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }

    fn age(path: &Path, seconds_ago: u64) {
        let at = SystemTime::now() - std::time::Duration::from_secs(seconds_ago);
        let file = std::fs::File::options().write(true).open(path).unwrap();
        file.set_modified(at).unwrap();
    }

    #[test]
    fn a_binary_older_than_a_source_of_a_crate_it_depends_on_is_refused_naming_it() {
        let root = tempfile::tempdir().unwrap();
        let root = root.path();
        let main = root.join("services/s/src/main.rs");
        write(
            &root.join("services/s/Cargo.toml"),
            "[package]\nname = \"s-service\"\n\n[[bin]]\nname = \"s\"\n\n\
             [dependencies]\nlib-a.workspace = true\nanyhow.workspace = true\n\n\
             [dev-dependencies]\nlib-c.workspace = true\n",
        );
        write(&main, "");
        write(
            &root.join("crates/a/Cargo.toml"),
            "[package]\nname = \"lib-a\"\n\n[dependencies]\nlib-b = { path = \"../b\" }\n",
        );
        let deep = root.join("crates/b/src/deep/mod.rs");
        write(
            &root.join("crates/b/Cargo.toml"),
            "[package]\nname = \"lib-b\"\n",
        );
        write(&deep, "");
        write(
            &root.join("crates/c/Cargo.toml"),
            "[package]\nname = \"lib-c\"\n",
        );
        let unrelated = root.join("crates/c/src/lib.rs");
        write(&unrelated, "");
        let bin = root.join("target/debug/s");
        assert_eq!(
            out_of_date(root, &bin, "s"),
            Some(format!("{} is missing", bin.display()))
        );
        write(&bin, "");
        for file in [&main, &deep] {
            age(file, 100);
        }
        age(&bin, 50);
        // Only what the binary is built from counts: lib-c is newer too.
        assert_eq!(out_of_date(root, &bin, "s"), None);
        age(&deep, 10);
        assert_eq!(
            out_of_date(root, &bin, "s"),
            Some(format!(
                "{} is older than {}",
                bin.display(),
                deep.display()
            ))
        );
    }
}
