//! Dataset files: writer/reader round trips, determinism of the output, and
//! the typed error (with line number and field path) of every kind of bad
//! line.

// clippy.toml allows these in #[test] functions only; the helpers below
// fail a test the same way.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::io::{self, BufRead, BufReader, Read};
use std::path::PathBuf;

use proptest::prelude::*;
use serde_json::json;
use vref_scene::{
    DatasetError, DatasetReader, DatasetWriter, GraphError, Limits, PairError, SceneGraph,
    SceneObject, ScenePair, Side, read_dataset_file,
};

// --------------------------------------------------------------- helpers

fn graph(objects: Vec<SceneObject>, edges: Option<Vec<[u64; 2]>>, limits: &Limits) -> SceneGraph {
    SceneGraph::new(objects, edges, limits).expect("valid graph")
}

/// A pair with edges on the robot side, features, awkward floats and ids.
fn rich_pair() -> ScenePair {
    let limits = Limits::default();
    let robot = graph(
        vec![
            SceneObject::new(
                10,
                [0.1 + 0.2, -0.0, 1.0 / 3.0],
                vec![0.1, 1.0 / 3.0, -7.5e-20],
            ),
            SceneObject::new(
                u64::MAX,
                [14304.829660047977, 1e5, -1e5],
                vec![f32::MAX, f32::MIN_POSITIVE, 0.0],
            ),
            SceneObject::new(
                12,
                [5e-324, std::f64::consts::PI, 0.013626999212273323],
                vec![1.0, 2.0, 3.0],
            ),
        ],
        Some(vec![[12, 10], [u64::MAX, 10], [10, 12]]),
        &limits,
    );
    let human = graph(
        vec![
            SceneObject::new(1, [0.3, 0.0, 0.0], vec![0.5, 0.25, 0.125]),
            SceneObject::new(2, [1.0e-7, 2.5, -3.75], vec![1e-38, -1e38, 3.4028235e38]),
        ],
        None,
        &limits,
    );
    ScenePair::new(
        "kitchen \"table\" \n\t é 🤖".to_owned(),
        robot,
        human,
        vec![(2, u64::MAX), (1, 10)],
    )
    .expect("valid pair")
}

/// A pair without any features and with an empty edge list.
fn plain_pair() -> ScenePair {
    let limits = Limits::default();
    let robot = graph(
        vec![
            SceneObject::new(0, [1.0, 2.0, 3.0], vec![]),
            SceneObject::new(1, [4.0, 5.0, 6.0], vec![]),
        ],
        Some(vec![]),
        &limits,
    );
    let human = graph(
        vec![SceneObject::new(0, [-1.0, -2.0, -3.0], vec![])],
        None,
        &limits,
    );
    ScenePair::new("plain".to_owned(), robot, human, vec![]).expect("valid pair")
}

fn write(pairs: &[ScenePair]) -> Vec<u8> {
    let mut writer = DatasetWriter::new(Vec::new());
    for pair in pairs {
        writer.write(pair).expect("write to memory");
    }
    writer.finish().expect("flush memory")
}

fn read(bytes: &[u8], limits: Limits) -> Vec<Result<ScenePair, DatasetError>> {
    DatasetReader::new(bytes, limits).collect()
}

fn read_ok(bytes: &[u8]) -> Vec<ScenePair> {
    read(bytes, Limits::default())
        .into_iter()
        .map(|r| r.expect("valid line"))
        .collect()
}

/// Bit-exact comparison of every coordinate and feature value (`==` on
/// floats would let -0.0 pass for 0.0).
fn assert_bits_equal(a: &ScenePair, b: &ScenePair) {
    assert_eq!(a, b);
    for (ga, gb) in [(&a.robot, &b.robot), (&a.human, &b.human)] {
        for (oa, ob) in ga.objects().iter().zip(gb.objects()) {
            let pa: Vec<u64> = oa.position.iter().map(|v| v.to_bits()).collect();
            let pb: Vec<u64> = ob.position.iter().map(|v| v.to_bits()).collect();
            assert_eq!(pa, pb, "position of object {}", oa.id);
            let fa: Vec<u32> = oa.feature.iter().map(|v| v.to_bits()).collect();
            let fb: Vec<u32> = ob.feature.iter().map(|v| v.to_bits()).collect();
            assert_eq!(fa, fb, "feature of object {}", oa.id);
        }
    }
}

/// A valid dataset line (as JSON) with two objects per view.
fn valid_value(name: &str) -> serde_json::Value {
    json!({
        "name": name,
        "robot": {"objects": [
            {"id": 10, "position": [0.0, 0.0, 1.0], "feature": [1.0, 0.0]},
            {"id": 11, "position": [0.5, 0.0, 1.0], "feature": [0.0, 1.0]}
        ]},
        "human": {"objects": [
            {"id": 1, "position": [0.0, 0.0, 2.0], "feature": [1.0, 0.0]},
            {"id": 2, "position": [0.5, 0.0, 2.0], "feature": [0.0, 1.0]}
        ]},
        "ground_truth": [[1, 10], [2, 11]]
    })
}

fn valid_line(name: &str) -> String {
    valid_value(name).to_string()
}

/// Reads one (non-blank) bad line at `line` preceded by `line - 1` valid
/// lines and followed by a valid line, and returns its error. Also checks
/// that the reader goes on with the line after it.
fn error_of(bad: &[u8], line: usize) -> DatasetError {
    let mut input = Vec::new();
    for i in 1..line {
        input.extend_from_slice(valid_line(&format!("before {i}")).as_bytes());
        input.push(b'\n');
    }
    input.extend_from_slice(bad);
    input.push(b'\n');
    input.extend_from_slice(valid_line("after").as_bytes());
    input.push(b'\n');

    let mut results = read(&input, Limits::default());
    assert_eq!(results.len(), line + 1, "one item per line");
    let after = results.pop().expect("line after the bad one");
    assert_eq!(after.expect("line after the bad one is read").name, "after");
    let err = results
        .pop()
        .expect("bad line")
        .expect_err("bad line gives an error");
    for (i, ok) in results.into_iter().enumerate() {
        assert_eq!(ok.expect("valid line").name, format!("before {}", i + 1));
    }
    assert_eq!(err.line(), Some(line), "{err}");
    err
}

/// The field path and message of a `Syntax` error on `line`.
fn syntax_of(bad: &[u8], line: usize) -> (String, String) {
    match error_of(bad, line) {
        DatasetError::Syntax {
            line: found,
            field,
            message,
        } => {
            assert_eq!(found, line);
            (field, message)
        }
        other => panic!("expected Syntax, got {other:?}"),
    }
}

/// The name and pair error of an `Invalid` error on `line`.
fn invalid_of(bad: &[u8], line: usize) -> (String, PairError) {
    match error_of(bad, line) {
        DatasetError::Invalid {
            line: found,
            name,
            source,
        } => {
            assert_eq!(found, line);
            (name, source)
        }
        other => panic!("expected Invalid, got {other:?}"),
    }
}

fn temp_path(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!(
        "vref-scene-test-{}-{tag}.jsonl",
        std::process::id()
    ))
}

// ------------------------------------------------------------ round trip

#[test]
fn round_trip_gives_equal_pairs() {
    let pairs = vec![rich_pair(), plain_pair(), rich_pair()];
    let back = read_ok(&write(&pairs));
    assert_eq!(back.len(), 3);
    for (a, b) in pairs.iter().zip(&back) {
        assert_bits_equal(a, b);
    }
}

#[test]
fn round_trip_keeps_edges_features_and_exact_floats() {
    let back = read_ok(&write(&[rich_pair()])).remove(0);
    assert_eq!(back.robot.edge_ids(), Some(vec![[10, u64::MAX], [10, 12]]));
    assert_eq!(back.robot.edges(), Some(&[(0, 1), (0, 2)][..]));
    assert_eq!(back.human.edges(), None);
    assert_eq!(back.robot.feature_dim(), 3);
    let first = &back.robot.objects()[0];
    assert_eq!(first.position.x.to_bits(), (0.1f64 + 0.2).to_bits());
    assert_ne!(first.position.x, 0.3);
    assert!(first.position.y.is_sign_negative(), "-0.0 stays negative");
    // Values serde_json parses one ulp off unless exact parsing is on.
    assert_eq!(
        back.robot.objects()[1].position.x.to_bits(),
        14304.829660047977f64.to_bits()
    );
    assert_eq!(
        back.robot.objects()[2].position.z.to_bits(),
        0.013626999212273323f64.to_bits()
    );
    assert_eq!(back.robot.objects()[2].position.x, 5e-324);
    assert_eq!(back.ground_truth, vec![(2, u64::MAX), (1, 10)]);
    assert_eq!(back.name, "kitchen \"table\" \n\t é 🤖");
}

#[test]
fn round_trip_without_features_and_with_empty_edges() {
    let back = read_ok(&write(&[plain_pair()])).remove(0);
    assert_bits_equal(&back, &plain_pair());
    assert_eq!(back.robot.feature_dim(), 0);
    assert!(back.robot.objects().iter().all(|o| o.feature.is_empty()));
    assert_eq!(back.robot.edges(), Some(&[][..]), "empty edge list is kept");
    assert_eq!(back.human.edges(), None);
}

#[test]
fn round_trip_of_empty_graphs_when_allowed() {
    let limits = Limits {
        require_objects: false,
        ..Limits::default()
    };
    let robot = graph(vec![], None, &limits);
    let human = graph(
        vec![SceneObject::new(3, [1.0, 1.0, 1.0], vec![0.5])],
        None,
        &limits,
    );
    let pair = ScenePair::new("empty robot".to_owned(), robot, human, vec![]).unwrap();
    let bytes = write(std::slice::from_ref(&pair));
    let back: Vec<_> = read(&bytes, limits)
        .into_iter()
        .map(Result::unwrap)
        .collect();
    assert_eq!(back, vec![pair]);
    // With the default limits the same line is refused, naming the side.
    let err = read(&bytes, Limits::default()).remove(0).unwrap_err();
    assert!(
        matches!(
            &err,
            DatasetError::Invalid {
                line: 1,
                source: PairError::Graph {
                    side: Side::Robot,
                    source: GraphError::Empty
                },
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn writer_output_is_one_compact_line_per_pair() {
    let bytes = write(&[plain_pair(), rich_pair()]);
    let text = String::from_utf8(bytes).unwrap();
    assert!(text.ends_with('\n'));
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2, "a newline in a name must be escaped");
    assert_eq!(
        lines[0],
        r#"{"name":"plain","robot":{"objects":[{"id":0,"position":[1.0,2.0,3.0]},{"id":1,"position":[4.0,5.0,6.0]}],"edges":[]},"human":{"objects":[{"id":0,"position":[-1.0,-2.0,-3.0]}]},"ground_truth":[]}"#
    );
    assert!(lines[1].contains(r#""position":[0.30000000000000004,-0.0,0.3333333333333333]"#));
}

#[test]
fn writing_twice_is_byte_identical() {
    let pairs = vec![rich_pair(), plain_pair()];
    let first = write(&pairs);
    let second = write(&pairs);
    assert_eq!(first, second);
    // And reading back then writing again changes nothing.
    assert_eq!(write(&read_ok(&first)), first);
}

#[test]
fn writer_reports_the_scene_it_could_not_write() {
    #[derive(Debug)]
    struct Broken;
    impl io::Write for Broken {
        fn write(&mut self, _: &[u8]) -> io::Result<usize> {
            Err(io::Error::new(io::ErrorKind::BrokenPipe, "gone"))
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }
    let mut writer = DatasetWriter::new(Broken);
    let err = writer.write(&plain_pair()).unwrap_err();
    match &err {
        DatasetError::Write { name, source } => {
            assert_eq!(name, "plain");
            assert_eq!(source.kind(), io::ErrorKind::BrokenPipe, "{source:?}");
        }
        other => panic!("expected Write, got {other:?}"),
    }
    assert_eq!(err.line(), None);
}

proptest! {
    /// Any finite position and feature value reads back bit for bit.
    #[test]
    fn round_trip_of_arbitrary_floats(
        position in prop::array::uniform3(-1.0e5f64..=1.0e5),
        tiny in prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO,
        feature in prop::collection::vec(
            prop::num::f32::NORMAL | prop::num::f32::SUBNORMAL | prop::num::f32::ZERO,
            0..8,
        ),
    ) {
        let limits = Limits::default();
        let tiny = if tiny.abs() <= limits.max_abs_coordinate { tiny } else { 1.0 / tiny };
        let robot = SceneGraph::new(
            vec![
                SceneObject::new(1, position, feature.clone()),
                SceneObject::new(2, [tiny, position[0], -position[1]], feature.clone()),
            ],
            None,
            &limits,
        ).unwrap();
        let human = SceneGraph::new(
            vec![SceneObject::new(1, [position[2], tiny, 0.0], feature)],
            None,
            &limits,
        ).unwrap();
        let pair = ScenePair::new("p".to_owned(), robot, human, vec![(1, 2)]).unwrap();
        let back = read_ok(&write(std::slice::from_ref(&pair)));
        prop_assert_eq!(back.len(), 1);
        assert_bits_equal(&back[0], &pair);
    }
}

// ------------------------------------------------------------ line layout

#[test]
fn blank_lines_are_skipped_but_counted() {
    let input = format!(
        "\n   \n{}\n\t\r\n\n{}\n\n{{}}\n  \n",
        valid_line("third"),
        valid_line("sixth")
    );
    let results = read(input.as_bytes(), Limits::default());
    assert_eq!(results.len(), 3);
    let mut results = results.into_iter();
    assert_eq!(results.next().unwrap().unwrap().name, "third");
    assert_eq!(results.next().unwrap().unwrap().name, "sixth");
    let err = results.next().unwrap().unwrap_err();
    assert_eq!(err.line(), Some(8), "{err}");
    assert!(
        matches!(err, DatasetError::Syntax { line: 8, .. }),
        "{err:?}"
    );
}

#[test]
fn empty_input_and_only_blank_lines_give_nothing() {
    assert!(read(b"", Limits::default()).is_empty());
    assert!(read(b"\n\n \r\n\t\n", Limits::default()).is_empty());
}

#[test]
fn crlf_line_endings_and_missing_final_newline_are_accepted() {
    let input = format!("{}\r\n{}", valid_line("a"), valid_line("b"));
    let names: Vec<String> = read_ok(input.as_bytes())
        .into_iter()
        .map(|p| p.name)
        .collect();
    assert_eq!(names, ["a", "b"]);
}

#[test]
fn pretty_printed_object_is_not_one_line() {
    // JSON Lines: an object spread over several lines is a syntax error on
    // its first line (and more errors after it), never silently accepted.
    let pretty = serde_json::to_string_pretty(&valid_value("p")).unwrap();
    let results = read(pretty.as_bytes(), Limits::default());
    assert!(results.len() > 1);
    let first = results[0].as_ref().unwrap_err();
    assert!(
        matches!(first, DatasetError::Syntax { line: 1, .. }),
        "{first:?}"
    );
    assert!(results.iter().all(Result::is_err));
}

// ------------------------------------------------------------ bad lines

#[test]
fn string_where_a_number_is_expected() {
    let mut value = valid_value("s");
    value["robot"]["objects"][1]["position"][0] = json!("0.5");
    let (field, message) = syntax_of(value.to_string().as_bytes(), 2);
    assert!(field.contains("robot.objects[1].position"), "{field}");
    assert!(message.contains("invalid type: string"), "{message}");
}

#[test]
fn negative_id() {
    let mut value = valid_value("s");
    value["human"]["objects"][0]["id"] = json!(-1);
    let (field, message) = syntax_of(value.to_string().as_bytes(), 1);
    assert_eq!(field, "human.objects[0].id");
    assert!(message.contains("-1"), "{message}");
}

#[test]
fn position_of_two_coordinates() {
    let mut value = valid_value("s");
    value["human"]["objects"][1]["position"] = json!([1.0, 2.0]);
    let (field, message) = syntax_of(value.to_string().as_bytes(), 3);
    assert_eq!(field, "human.objects[1].position");
    assert!(message.contains("invalid length 2"), "{message}");
}

#[test]
fn unknown_top_level_field() {
    let mut value = valid_value("s");
    value["colour"] = json!("red");
    let (field, message) = syntax_of(value.to_string().as_bytes(), 2);
    assert_eq!(field, "colour");
    assert!(message.contains("unknown field `colour`"), "{message}");
}

#[test]
fn unknown_object_field() {
    let mut value = valid_value("s");
    value["robot"]["objects"][0]["label"] = json!("cup");
    let (field, message) = syntax_of(value.to_string().as_bytes(), 1);
    assert_eq!(field, "robot.objects[0].label");
    assert!(message.contains("unknown field `label`"), "{message}");
}

#[test]
fn missing_ground_truth() {
    let mut value = valid_value("s");
    value.as_object_mut().unwrap().remove("ground_truth");
    let (field, message) = syntax_of(value.to_string().as_bytes(), 4);
    assert_eq!(field, ".");
    assert!(
        message.contains("missing field `ground_truth`"),
        "{message}"
    );
}

#[test]
fn missing_position() {
    let mut value = valid_value("s");
    value["human"]["objects"][1]
        .as_object_mut()
        .unwrap()
        .remove("position");
    let (field, message) = syntax_of(value.to_string().as_bytes(), 1);
    assert_eq!(field, "human.objects[1]");
    assert!(message.contains("missing field `position`"), "{message}");
}

#[test]
fn truncated_json() {
    let line = valid_line("s");
    let cut = line.find("\"ground_truth\"").unwrap() + "\"ground_truth\":[[1,".len();
    let (field, message) = syntax_of(&line.as_bytes()[..cut], 2);
    assert_eq!(field, "ground_truth[0]");
    assert!(message.contains("EOF"), "{message}");
}

#[test]
fn trailing_garbage_after_the_object() {
    for garbage in [" x", "{}", ",", "]"] {
        let line = format!("{}{garbage}", valid_line("s"));
        let (field, message) = syntax_of(line.as_bytes(), 2);
        assert_eq!(field, ".");
        assert!(
            message.contains("trailing characters"),
            "{garbage:?}: {message}"
        );
    }
}

#[test]
fn number_out_of_range() {
    let mut value = valid_value("s");
    value["robot"]["objects"][1]["position"][0] = json!("HUGE");
    let line = value.to_string().replacen("\"HUGE\"", "1e400", 1);
    let (field, message) = syntax_of(line.as_bytes(), 1);
    assert_eq!(field, "robot.objects[1].position[0]");
    assert!(message.contains("number out of range"), "{message}");
}

#[test]
fn id_beyond_u64() {
    let line = valid_line("s").replacen("\"id\":10", "\"id\":18446744073709551616", 1);
    assert_ne!(line, valid_line("s"));
    let (field, _) = syntax_of(line.as_bytes(), 1);
    assert_eq!(field, "robot.objects[0].id");
}

#[test]
fn non_utf8_line() {
    // Invalid UTF-8 inside the name string.
    let mut rest = valid_value("");
    rest.as_object_mut().unwrap().remove("name");
    let mut line = br#"{"name":"caf"#.to_vec();
    line.extend_from_slice(b"\xE9\",");
    line.extend_from_slice(&rest.to_string().as_bytes()[1..]);
    assert!(std::str::from_utf8(&line).is_err());
    let (field, message) = syntax_of(&line, 2);
    assert_eq!(field, "name");
    assert!(message.contains("unicode"), "{message}");

    // Invalid UTF-8 outside any string.
    let (field, message) = syntax_of(&[0xFF, 0xFE, b'{', b'}'], 1);
    assert_eq!(field, ".");
    assert!(message.contains("expected value"), "{message}");
}

#[test]
fn not_an_object() {
    for (line, expected) in [
        ("null", "null"),
        ("42", "integer"),
        ("\"scene\"", "string"),
        ("[]", "sequence"),
    ] {
        let (field, message) = syntax_of(line.as_bytes(), 1);
        assert_eq!(field, ".", "{line}");
        assert!(message.contains(expected), "{line}: {message}");
    }
}

#[test]
fn array_in_place_of_an_object_is_refused() {
    // Derived serde structs also accept an array of field values; the
    // dataset format does not.
    let value = valid_value("s");
    let array = json!(["s", value["robot"], value["human"], value["ground_truth"]]);
    let (field, message) = syntax_of(array.to_string().as_bytes(), 1);
    assert_eq!(field, ".");
    assert!(message.contains("expected a JSON object"), "{message}");

    let mut graph_as_array = valid_value("s");
    graph_as_array["robot"] = json!([value["robot"]["objects"]]);
    let (field, message) = syntax_of(graph_as_array.to_string().as_bytes(), 1);
    assert_eq!(field, "robot");
    assert!(message.contains("expected a JSON object"), "{message}");

    let mut object_as_array = valid_value("s");
    object_as_array["human"]["objects"][1] = json!([2, [0.5, 0.0, 2.0], [0.0, 1.0]]);
    let (field, message) = syntax_of(object_as_array.to_string().as_bytes(), 1);
    assert_eq!(field, "human.objects[1]");
    assert!(message.contains("expected a JSON object"), "{message}");
}

#[test]
fn duplicate_field() {
    let line = valid_line("s").replacen('{', r#"{"name":"t","#, 1);
    let (field, message) = syntax_of(line.as_bytes(), 1);
    assert_eq!(field, ".");
    assert!(message.contains("duplicate field `name`"), "{message}");
}

#[test]
fn valid_json_but_duplicate_id_is_invalid() {
    let mut value = valid_value("dup scene");
    value["robot"]["objects"][1]["id"] = json!(10);
    let (name, source) = invalid_of(value.to_string().as_bytes(), 3);
    assert_eq!(name, "dup scene");
    assert_eq!(
        source,
        PairError::Graph {
            side: Side::Robot,
            source: GraphError::DuplicateId { id: 10 }
        }
    );
}

#[test]
fn feature_beyond_f32_is_refused() {
    // 1e39 is a fine f64 but beyond f32: it must not become an infinity.
    let mut value = valid_value("big");
    value["human"]["objects"][1]["feature"][0] = json!(1e39);
    let (field, message) = syntax_of(value.to_string().as_bytes(), 1);
    assert_eq!(field, "human.objects[1].feature[0]");
    assert!(message.contains("number out of range"), "{message}");
}

#[test]
fn absurd_position_in_a_line_is_invalid() {
    let mut value = valid_value("far");
    value["human"]["objects"][0]["position"][2] = json!(1e6);
    let (_, source) = invalid_of(value.to_string().as_bytes(), 2);
    assert_eq!(
        source,
        PairError::Graph {
            side: Side::Human,
            source: GraphError::AbsurdPosition {
                id: 1,
                axis: 2,
                value: 1e6,
                limit: 1e5
            }
        }
    );
}

#[test]
fn unknown_edge_endpoint_in_a_line_is_invalid() {
    let mut value = valid_value("edges");
    value["robot"]["edges"] = json!([[10, 11], [11, 12]]);
    let (_, source) = invalid_of(value.to_string().as_bytes(), 1);
    assert_eq!(
        source,
        PairError::Graph {
            side: Side::Robot,
            source: GraphError::UnknownEdgeEndpoint {
                a: 11,
                b: 12,
                unknown: 12
            }
        }
    );
}

#[test]
fn pair_level_defects_in_a_line_are_invalid() {
    let mut value = valid_value("gt");
    value["ground_truth"] = json!([[1, 10], [2, 10]]);
    let (name, source) = invalid_of(value.to_string().as_bytes(), 2);
    assert_eq!(name, "gt");
    assert_eq!(
        source,
        PairError::GroundTruthNotOneToOne {
            index: 1,
            side: Side::Robot,
            id: 10
        }
    );

    let mut value = valid_value("gt");
    value["ground_truth"] = json!([[3, 10]]);
    let (_, source) = invalid_of(value.to_string().as_bytes(), 1);
    assert_eq!(
        source,
        PairError::UnknownGroundTruthId {
            index: 0,
            side: Side::Human,
            id: 3
        }
    );

    let mut value = valid_value("dims");
    value["robot"]["objects"][0]["feature"] = json!([1.0, 0.0, 0.0]);
    value["robot"]["objects"][1]["feature"] = json!([0.0, 1.0, 0.0]);
    let (_, source) = invalid_of(value.to_string().as_bytes(), 1);
    assert_eq!(source, PairError::FeatureDimsDiffer { human: 2, robot: 3 });
}

#[test]
fn reader_goes_on_after_each_bad_line() {
    let mut dup = valid_value("dup");
    dup["human"]["objects"][1]["id"] = json!(1);
    let input = [
        valid_line("one"),
        "{".to_owned(),
        String::new(),
        dup.to_string(),
        "[1, 2]".to_owned(),
        valid_line("six"),
        "nonsense".to_owned(),
        valid_line("eight"),
    ]
    .join("\n");
    let results = read(input.as_bytes(), Limits::default());
    let summary: Vec<(Option<usize>, &str)> = results
        .iter()
        .map(|r| match r {
            Ok(pair) => (None, pair.name.as_str()),
            Err(DatasetError::Syntax { line, .. }) => (Some(*line), "syntax"),
            Err(DatasetError::Invalid { line, name, .. }) => {
                assert_eq!(name, "dup");
                (Some(*line), "invalid")
            }
            Err(other) => panic!("unexpected {other:?}"),
        })
        .collect();
    assert_eq!(
        summary,
        [
            (None, "one"),
            (Some(2), "syntax"),
            (Some(4), "invalid"),
            (Some(5), "syntax"),
            (None, "six"),
            (Some(7), "syntax"),
            (None, "eight"),
        ]
    );
}

#[test]
fn errors_display_their_line_and_field() {
    let mut value = valid_value("s");
    value["robot"]["objects"][1]["position"][0] = json!("x");
    let text = error_of(value.to_string().as_bytes(), 5).to_string();
    assert!(
        text.starts_with("line 5: field `robot.objects[1].position"),
        "{text}"
    );

    let mut value = valid_value("named");
    value["robot"]["objects"][1]["id"] = json!(10);
    // The cause is the error's source, not repeated in its message, so
    // that a printed chain says each thing once.
    let err = error_of(value.to_string().as_bytes(), 2);
    assert_eq!(err.to_string(), "line 2 (scene \"named\")");
    let graph = std::error::Error::source(&err).expect("pair error");
    assert_eq!(graph.to_string(), "robot graph");
    let cause = graph.source().expect("graph error");
    assert_eq!(cause.to_string(), "object id 10 appears more than once");
}

#[test]
fn line_of_each_error() {
    let io = || io::Error::other("x");
    let pair_error = PairError::FeatureDimsDiffer { human: 1, robot: 2 };
    let cases = [
        (
            DatasetError::Open {
                path: "p".into(),
                source: io(),
            },
            None,
        ),
        (
            DatasetError::Io {
                line: 3,
                source: io(),
            },
            Some(3),
        ),
        (DatasetError::LineTooLong { line: 4, limit: 1 }, Some(4)),
        (
            DatasetError::Syntax {
                line: 5,
                field: ".".into(),
                message: String::new(),
            },
            Some(5),
        ),
        (
            DatasetError::Invalid {
                line: 6,
                name: String::new(),
                source: pair_error,
            },
            Some(6),
        ),
        (
            DatasetError::Write {
                name: String::new(),
                source: io(),
            },
            None,
        ),
    ];
    for (err, line) in cases {
        assert_eq!(err.line(), line, "{err:?}");
    }
}

// ------------------------------------------------------ I/O and limits

/// Serves `good` bytes, then fails every read.
struct FailAfter {
    good: io::Cursor<Vec<u8>>,
}

impl Read for FailAfter {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        match self.good.read(buf)? {
            0 => Err(io::Error::new(
                io::ErrorKind::ConnectionReset,
                "cable pulled",
            )),
            n => Ok(n),
        }
    }
}

#[test]
fn io_error_ends_the_stream_with_its_line() {
    let good = format!("{}\n\n{}", valid_line("one"), &valid_line("cut")[..20]);
    let input = BufReader::new(FailAfter {
        good: io::Cursor::new(good.into_bytes()),
    });
    let mut reader = DatasetReader::new(input, Limits::default());
    assert_eq!(reader.next().unwrap().unwrap().name, "one");
    let err = reader.next().unwrap().unwrap_err();
    match &err {
        DatasetError::Io { line, source } => {
            assert_eq!(*line, 3);
            assert_eq!(source.kind(), io::ErrorKind::ConnectionReset);
        }
        other => panic!("expected Io, got {other:?}"),
    }
    assert!(reader.next().is_none(), "no more items after an I/O error");
    assert!(reader.next().is_none());
}

/// `len` bytes of `fill`, then `rest`, without holding them all in memory.
struct Generated {
    remaining: usize,
    fill: u8,
    rest: io::Cursor<Vec<u8>>,
}

impl Read for Generated {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.remaining == 0 {
            return self.rest.read(buf);
        }
        let n = buf.len().min(self.remaining);
        buf[..n].fill(self.fill);
        self.remaining -= n;
        Ok(n)
    }
}

const MAX_LINE_BYTES: usize = 64 * 1024 * 1024;

fn generated(len: usize, fill: u8, rest: String) -> impl BufRead {
    BufReader::with_capacity(
        1 << 20,
        Generated {
            remaining: len,
            fill,
            rest: io::Cursor::new(rest.into_bytes()),
        },
    )
}

#[test]
fn over_long_line_is_refused_and_the_reader_goes_on() {
    let rest = format!("\n{}\n", valid_line("after"));
    let input = generated(MAX_LINE_BYTES + 1000, b'x', rest);
    let results: Vec<_> = DatasetReader::new(input, Limits::default()).collect();
    assert_eq!(results.len(), 2);
    match &results[0] {
        Err(DatasetError::LineTooLong { line: 1, limit }) => assert_eq!(*limit, MAX_LINE_BYTES),
        other => panic!("expected LineTooLong on line 1, got {other:?}"),
    }
    let after = results[1].as_ref().expect("line after the long one");
    assert_eq!(after.name, "after");
}

#[test]
fn line_of_exactly_the_limit_is_not_too_long() {
    // Blank padding keeps it cheap to parse; the newline is not counted.
    let line = valid_line("at limit");
    let input = generated(
        MAX_LINE_BYTES - line.len(),
        b' ',
        format!("{line}\n{}", valid_line("b")),
    );
    let results: Vec<_> = DatasetReader::new(input, Limits::default())
        .map(|r| r.map(|p| p.name))
        .collect();
    assert_eq!(results.len(), 2, "{results:?}");
    assert_eq!(results[0].as_ref().unwrap(), "at limit");
    assert_eq!(results[1].as_ref().unwrap(), "b");

    let input = generated(MAX_LINE_BYTES + 1 - line.len(), b' ', format!("{line}\n"));
    let results: Vec<_> = DatasetReader::new(input, Limits::default()).collect();
    assert_eq!(results.len(), 1);
    assert!(matches!(
        results[0],
        Err(DatasetError::LineTooLong { line: 1, .. })
    ));
}

#[test]
fn read_dataset_file_round_trip() {
    let path = temp_path("round-trip");
    let pairs = vec![rich_pair(), plain_pair()];
    std::fs::write(&path, write(&pairs)).unwrap();
    let back = read_dataset_file(&path, Limits::default());
    std::fs::remove_file(&path).unwrap();
    assert_eq!(back.unwrap(), pairs);
}

#[test]
fn read_dataset_file_stops_at_the_first_bad_line() {
    let path = temp_path("bad-line");
    let content = format!(
        "{}\n\n{{\"name\":1}}\n{}\n",
        valid_line("a"),
        valid_line("b")
    );
    std::fs::write(&path, content).unwrap();
    let result = read_dataset_file(&path, Limits::default());
    std::fs::remove_file(&path).unwrap();
    let err = result.unwrap_err();
    match &err {
        DatasetError::Syntax { line, field, .. } => {
            assert_eq!(*line, 3);
            assert_eq!(field, "name");
        }
        other => panic!("expected Syntax, got {other:?}"),
    }
}

#[test]
fn read_dataset_file_on_a_missing_path() {
    let path = temp_path("does-not-exist");
    let err = read_dataset_file(&path, Limits::default()).unwrap_err();
    match &err {
        DatasetError::Open { path: p, source } => {
            assert_eq!(p, &path);
            assert_eq!(source.kind(), io::ErrorKind::NotFound);
        }
        other => panic!("expected Open, got {other:?}"),
    }
    assert_eq!(err.line(), None);
    assert!(err.to_string().contains("does-not-exist"), "{err}");
}

#[test]
fn a_view_may_carry_its_up_vector_kept_as_unit_length() {
    let mut value = valid_value("gravity");
    value["human"]["up"] = json!([0.0, -2.0, 0.0]);
    let pairs = read_ok(format!("{value}\n").as_bytes());
    let up = pairs[0].human.up().expect("human up");
    assert_eq!([up.x, up.y, up.z], [0.0, -1.0, 0.0]);
    assert_eq!(pairs[0].robot.up(), None);
    // Written and read again: the same.
    let again = read_ok(&write(&pairs));
    assert_eq!(again[0].human.up(), pairs[0].human.up());
    assert_eq!(again[0].robot.up(), None);
}

#[test]
fn an_up_vector_that_is_no_direction_is_invalid() {
    for bad in [json!([0.0, 0.0, 0.0]), json!([0.0, 1e-9, 0.0])] {
        let mut value = valid_value("no up");
        value["robot"]["up"] = bad;
        let (name, source) = invalid_of(value.to_string().as_bytes(), 2);
        assert_eq!(name, "no up");
        assert!(
            matches!(
                source,
                PairError::Graph {
                    side: Side::Robot,
                    source: GraphError::BadUp { .. }
                }
            ),
            "{source:?}"
        );
    }
}
