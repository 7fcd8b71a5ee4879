//! The dataset fuzz target's committed corpus (fuzz/corpus/dataset_line),
//! read without cargo-fuzz: seeds named `valid*`, `two_lines` and
//! `blank_*` read without error, the other named seeds give at least one
//! error, and any regression input added later must simply not panic.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use vref_scene::{DatasetReader, Limits};

#[test]
fn every_corpus_input_reads_or_fails_with_an_error_without_panicking() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus/dataset_line");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() >= 6, "corpus too small: {files:?}");
    let (mut good, mut bad) = (0, 0);
    for file in &files {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let bytes = std::fs::read(file).unwrap();
        let items: Vec<_> = DatasetReader::new(bytes.as_slice(), Limits::default()).collect();
        let errors = items.iter().filter(|i| i.is_err()).count();
        if ["valid", "two_lines", "blank"]
            .iter()
            .any(|p| name.starts_with(p))
        {
            assert_eq!(errors, 0, "{name}: {items:?}");
            assert!(!items.is_empty(), "{name}");
            good += 1;
        } else if !name.starts_with("regression") {
            assert!(errors > 0, "{name} should give an error: {items:?}");
            bad += 1;
        }
    }
    assert!(good >= 3 && bad >= 3, "{good} good, {bad} bad");
}
