//! Whatever bytes a dataset holds, the reader never panics, ends, and every
//! error it yields names a line that exists in the input.

// clippy.toml allows these in #[test] functions only; the helpers below
// fail a test the same way.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use proptest::prelude::*;
use vref_scene::{
    DatasetError, DatasetReader, DatasetWriter, Limits, SceneGraph, SceneObject, ScenePair,
};

/// A valid dataset line to mutate: edges, features, ground truth.
fn valid_line() -> Vec<u8> {
    let limits = Limits::default();
    let robot = SceneGraph::new(
        vec![
            SceneObject::new(10, [0.1, 0.2, 1.5], vec![1.0, 0.0, 0.25]),
            SceneObject::new(11, [-0.5, 0.0, 1.0], vec![0.0, 1.0, -0.5]),
            SceneObject::new(12, [0.0, 0.5, 1e-3], vec![0.5, 0.5, 0.0]),
        ],
        Some(vec![[10, 11], [11, 12]]),
        &limits,
    )
    .expect("valid robot graph");
    let human = SceneGraph::new(
        vec![
            SceneObject::new(1, [0.0, 0.0, 2.0], vec![1.0, 0.0, 0.0]),
            SceneObject::new(2, [0.5, 0.0, 2.0], vec![0.0, 1.0, 0.0]),
        ],
        None,
        &limits,
    )
    .expect("valid human graph");
    let pair = ScenePair::new(
        "fuzz \"seed\"".to_owned(),
        robot,
        human,
        vec![(1, 10), (2, 12)],
    )
    .expect("valid pair");
    let mut writer = DatasetWriter::new(Vec::new());
    writer.write(&pair).expect("write to memory");
    let mut line = writer.finish().expect("flush memory");
    assert_eq!(line.pop(), Some(b'\n'));
    line
}

/// Lines in `input` as an editor counts them (a final line without a
/// newline counts; an empty input has none).
fn line_count(input: &[u8]) -> usize {
    let newlines = input.iter().filter(|&&b| b == b'\n').count();
    newlines + usize::from(input.last().is_some_and(|&b| b != b'\n'))
}

/// Reads `input` to the end and checks every item; returns the results.
fn check(input: &[u8]) -> Result<Vec<Result<ScenePair, DatasetError>>, TestCaseError> {
    let lines = line_count(input);
    let results: Vec<_> = DatasetReader::new(input, Limits::default()).collect();
    prop_assert!(
        results.len() <= lines,
        "{} items from {lines} lines",
        results.len()
    );
    let mut previous = 0;
    for result in &results {
        if let Err(err) = result {
            let line = err.line();
            prop_assert!(line.is_some(), "error without a line: {err:?}");
            let line = line.unwrap_or_default();
            prop_assert!((1..=lines).contains(&line), "line {line} of {lines}: {err}");
            prop_assert!(line > previous, "line {line} after {previous}: {err}");
            prop_assert!(
                matches!(
                    err,
                    DatasetError::Syntax { .. } | DatasetError::Invalid { .. }
                ),
                "in-memory input can only have bad content: {err:?}"
            );
            prop_assert!(
                err.to_string().starts_with(&format!("line {line}")),
                "{err}"
            );
            previous = line;
        }
    }
    Ok(results)
}

/// One edit of a valid line.
#[derive(Debug, Clone)]
enum Mutation {
    /// XOR the byte at (index mod len) with a non-zero mask.
    Flip(usize, u8),
    /// Replace the byte at (index mod len).
    Set(usize, u8),
    /// Keep only the first (index mod len) bytes.
    Truncate(usize),
    /// Remove the byte at (index mod len).
    Delete(usize),
    /// Insert a byte before (index mod len).
    Insert(usize, u8),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    // Bytes that matter to JSON are likelier than uniform bytes would be.
    let byte = prop_oneof![
        any::<u8>(),
        prop::sample::select(b"{}[]\",:0123456789-+.eE \n\r\\tfnu".to_vec()),
    ];
    prop_oneof![
        (any::<usize>(), 1..=u8::MAX).prop_map(|(i, m)| Mutation::Flip(i, m)),
        (any::<usize>(), byte.clone()).prop_map(|(i, b)| Mutation::Set(i, b)),
        any::<usize>().prop_map(Mutation::Truncate),
        any::<usize>().prop_map(Mutation::Delete),
        (any::<usize>(), byte).prop_map(|(i, b)| Mutation::Insert(i, b)),
    ]
}

fn apply(line: &mut Vec<u8>, mutation: &Mutation) {
    if line.is_empty() {
        return;
    }
    let len = line.len();
    match *mutation {
        Mutation::Flip(i, mask) => line[i % len] ^= mask,
        Mutation::Set(i, b) => line[i % len] = b,
        Mutation::Truncate(i) => line.truncate(i % len),
        Mutation::Delete(i) => {
            line.remove(i % len);
        }
        Mutation::Insert(i, b) => line.insert(i % len, b),
    }
}

#[test]
fn the_seed_line_is_valid() {
    let line = valid_line();
    let results = DatasetReader::new(&line[..], Limits::default()).collect::<Vec<_>>();
    assert_eq!(results.len(), 1);
    assert_eq!(results[0].as_ref().expect("valid").name, "fuzz \"seed\"");
}

proptest! {
    #[test]
    fn arbitrary_strings_never_panic(input in any::<String>()) {
        check(input.as_bytes())?;
    }

    #[test]
    fn arbitrary_json_like_text_never_panics(
        input in "[{}\\[\\]\",:0-9a-z\\-+.eE \n\r\t\\\\]{0,200}",
    ) {
        check(input.as_bytes())?;
    }

    #[test]
    fn arbitrary_bytes_never_panic(input in prop::collection::vec(any::<u8>(), 0..512)) {
        check(&input)?;
    }

    #[test]
    fn mutated_valid_lines_never_panic(
        mutations in prop::collection::vec(mutation(), 1..6),
        repeat in 1usize..4,
    ) {
        let seed = valid_line();
        let mut line = seed.clone();
        for m in &mutations {
            apply(&mut line, m);
        }
        // The mutated line a few times, then an intact line: the reader
        // must recover and read the intact one.
        let mut input = Vec::new();
        for _ in 0..repeat {
            input.extend_from_slice(&line);
            input.push(b'\n');
        }
        input.extend_from_slice(&seed);
        input.push(b'\n');
        let results = check(&input)?;
        let last = results.last().map(|r| r.as_ref().map(|p| p.name.clone()));
        prop_assert!(
            matches!(&last, Some(Ok(name)) if name == "fuzz \"seed\""),
            "intact last line not read: {last:?}"
        );
        // An unchanged line reads as the seed; a line still valid after the
        // edits reads as some pair; anything else is a typed error.
        if line == seed {
            prop_assert!(results.iter().all(Result::is_ok));
        }
    }
}
