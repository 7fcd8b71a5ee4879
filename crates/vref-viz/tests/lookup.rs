#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::io::Cursor;

use vref_scene::{DatasetError, DatasetReader, DatasetWriter, Limits, ScenePair};
use vref_viz::{SceneLookupError, find_scene};

fn named(name: &str) -> ScenePair {
    let mut pair = common::cmu_like(4);
    pair.name = name.to_owned();
    pair
}

fn dataset(names: &[&str]) -> Vec<u8> {
    let mut writer = DatasetWriter::new(Vec::new());
    for name in names {
        writer.write(&named(name)).unwrap();
    }
    writer.finish().unwrap()
}

fn reader(bytes: &[u8]) -> DatasetReader<Cursor<&[u8]>> {
    DatasetReader::new(Cursor::new(bytes), Limits::default())
}

#[test]
fn finds_a_scene_by_name() {
    let bytes = dataset(&["house1-house51", "house2-house52", "house3-house53"]);
    let pair = find_scene(reader(&bytes), "house2-house52").unwrap();
    assert_eq!(pair.name, "house2-house52");
}

#[test]
fn an_unknown_name_lists_close_names_first() {
    let names: Vec<String> = (1..=20)
        .map(|k| format!("house{k}-house{}", k + 50))
        .collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let bytes = dataset(&names);
    let error = find_scene(reader(&bytes), "house13").unwrap_err();
    let SceneLookupError::UnknownScene {
        name,
        total,
        examples,
    } = &error
    else {
        panic!("expected UnknownScene, got {error}");
    };
    assert_eq!(name, "house13");
    assert_eq!(*total, 20);
    assert_eq!(
        examples.first().map(String::as_str),
        Some("house13-house63")
    );
    assert!(examples.len() <= 5);
    let message = error.to_string();
    assert!(message.contains("\"house13\""), "{message}");
    assert!(message.contains("20 scenes"), "{message}");
    assert!(message.contains("house13-house63"), "{message}");
}

#[test]
fn an_unknown_name_in_an_empty_file_says_so() {
    let error = find_scene(reader(b""), "anything").unwrap_err();
    assert!(
        matches!(&error, SceneLookupError::UnknownScene { total: 0, examples, .. } if examples.is_empty()),
        "{error}"
    );
}

#[test]
fn a_bad_line_before_the_scene_is_an_error() {
    let mut bytes = b"{\"name\": \"broken\"}\n".to_vec();
    bytes.extend(dataset(&["wanted"]));
    let error = find_scene(reader(&bytes), "wanted").unwrap_err();
    assert!(
        matches!(
            error,
            SceneLookupError::Dataset(DatasetError::Syntax { line: 1, .. })
        ),
        "{error}"
    );
}
