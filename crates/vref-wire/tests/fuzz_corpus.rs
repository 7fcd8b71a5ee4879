//! The snapshot fuzz target's committed corpus (fuzz/corpus/snapshot),
//! run through the same decoding and validation without cargo-fuzz: seeds
//! named `valid_*` pass, `bad_up_*` are refused for their up vector, the
//! other named seeds are refused, and any regression input added later
//! must simply not panic.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use vref_scene::{GraphError, Limits};
use vref_wire::fuzz_input::snapshot_from_bytes;
use vref_wire::{SnapshotHeader, WireError, validate_snapshot};

#[test]
fn every_corpus_input_validates_or_is_refused_without_panicking() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus/snapshot");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() >= 10, "corpus too small: {files:?}");
    let (mut valid, mut refused) = (0, 0);
    for file in &files {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let s = snapshot_from_bytes(&std::fs::read(file).unwrap());
        let result = validate_snapshot(&s.header, &s.entries, s.expected, &Limits::default());
        if name.starts_with("valid") {
            let snapshot = result.unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(
                snapshot.graph.len(),
                s.header.object_count as usize,
                "{name}"
            );
            assert_eq!(
                snapshot.graph.up().is_some(),
                s.header.flags & SnapshotHeader::FLAG_UP != 0,
                "{name}"
            );
            valid += 1;
        } else if name.starts_with("bad_up") {
            assert!(
                matches!(result, Err(WireError::Graph(GraphError::BadUp { .. }))),
                "{name}: {result:?}"
            );
            refused += 1;
        } else if !name.starts_with("regression") {
            assert!(result.is_err(), "{name} should be refused");
            refused += 1;
        }
    }
    assert!(
        valid >= 2 && refused >= 8,
        "{valid} valid, {refused} refused"
    );
}
