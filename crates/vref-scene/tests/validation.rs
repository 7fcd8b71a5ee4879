//! Every defect `SceneGraph::new` and `ScenePair::new` refuse, one test per
//! error variant, and what a valid graph looks like after validation.

// clippy.toml allows these in #[test] functions only; the helpers below
// fail a test the same way.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use vref_scene::{GraphError, Limits, PairError, SceneGraph, SceneObject, ScenePair, Side};

fn obj(id: u64, position: [f64; 3], feature: &[f32]) -> SceneObject {
    SceneObject::new(id, position, feature.to_vec())
}

/// Three objects with 2-dimensional features, ids 1, 2, 3.
fn three_objects() -> Vec<SceneObject> {
    vec![
        obj(1, [0.0, 0.0, 0.0], &[1.0, 0.0]),
        obj(2, [1.0, 0.0, 0.0], &[0.0, 1.0]),
        obj(3, [0.0, 1.0, 0.5], &[0.5, 0.5]),
    ]
}

fn graph_err(objects: Vec<SceneObject>, edges: Option<Vec<[u64; 2]>>) -> GraphError {
    SceneGraph::new(objects, edges, &Limits::default()).expect_err("graph should be refused")
}

fn valid_graph(objects: Vec<SceneObject>) -> SceneGraph {
    SceneGraph::new(objects, None, &Limits::default()).expect("graph should be valid")
}

// ---------------------------------------------------------------- graphs

#[test]
fn valid_graph_is_accepted() {
    let graph = valid_graph(three_objects());
    assert_eq!(graph.len(), 3);
    assert!(!graph.is_empty());
    assert_eq!(graph.feature_dim(), 2);
    assert_eq!(graph.edges(), None, "no edge list means fully connected");
    assert_eq!(graph.edge_ids(), None);
    assert_eq!(graph.objects(), three_objects().as_slice());
}

#[test]
fn graph_without_features_has_dimension_zero() {
    let graph = valid_graph(vec![
        obj(7, [1.0, 2.0, 3.0], &[]),
        obj(8, [3.0, 2.0, 1.0], &[]),
    ]);
    assert_eq!(graph.feature_dim(), 0);
    assert_eq!(graph.len(), 2);
}

#[test]
fn index_of_finds_every_id_and_nothing_else() {
    let graph = valid_graph(vec![
        obj(40, [0.0; 3], &[]),
        obj(10, [1.0; 3], &[]),
        obj(u64::MAX, [2.0; 3], &[]),
    ]);
    assert_eq!(graph.index_of(40), Some(0));
    assert_eq!(graph.index_of(10), Some(1));
    assert_eq!(graph.index_of(u64::MAX), Some(2));
    assert_eq!(graph.index_of(11), None);
    assert_eq!(graph.index_of(0), None);
}

#[test]
fn edges_are_normalised_sorted_and_deduplicated() {
    let edges = vec![[3, 1], [2, 1], [1, 3], [1, 2], [3, 2], [2, 3], [3, 1]];
    let graph = SceneGraph::new(three_objects(), Some(edges), &Limits::default()).unwrap();
    assert_eq!(graph.edges(), Some(&[(0, 1), (0, 2), (1, 2)][..]));
    assert_eq!(graph.edge_ids(), Some(vec![[1, 2], [1, 3], [2, 3]]));
}

#[test]
fn edges_are_ordered_by_index_not_by_id() {
    // Object order 30, 20, 10: the edge [10, 30] is (0, 2) by index.
    let objects = vec![
        obj(30, [0.0; 3], &[]),
        obj(20, [1.0; 3], &[]),
        obj(10, [2.0; 3], &[]),
    ];
    let graph =
        SceneGraph::new(objects, Some(vec![[10, 20], [10, 30]]), &Limits::default()).unwrap();
    assert_eq!(graph.edges(), Some(&[(0, 2), (1, 2)][..]));
    assert_eq!(graph.edge_ids(), Some(vec![[30, 10], [20, 10]]));
}

#[test]
fn empty_edge_list_is_not_fully_connected() {
    let graph = SceneGraph::new(three_objects(), Some(vec![]), &Limits::default()).unwrap();
    assert_eq!(graph.edges(), Some(&[][..]));
    assert_eq!(graph.edge_ids(), Some(vec![]));
}

#[test]
fn empty_graph_is_refused_when_objects_are_required() {
    let limits = Limits {
        require_objects: true,
        ..Limits::default()
    };
    assert_eq!(
        SceneGraph::new(vec![], None, &limits),
        Err(GraphError::Empty)
    );
    assert_eq!(
        SceneGraph::new(vec![], Some(vec![]), &limits),
        Err(GraphError::Empty)
    );
}

#[test]
fn empty_graph_is_accepted_when_objects_are_optional() {
    let limits = Limits {
        require_objects: false,
        ..Limits::default()
    };
    let graph = SceneGraph::new(vec![], None, &limits).unwrap();
    assert!(graph.is_empty());
    assert_eq!(graph.len(), 0);
    assert_eq!(graph.feature_dim(), 0);
    assert_eq!(graph.index_of(0), None);
}

#[test]
fn too_many_objects() {
    let limits = Limits {
        capacity: 2,
        ..Limits::default()
    };
    let err = SceneGraph::new(three_objects(), None, &limits).unwrap_err();
    assert_eq!(
        err,
        GraphError::TooManyObjects {
            count: 3,
            capacity: 2
        }
    );
    // Exactly at capacity is fine.
    let at_capacity = three_objects().into_iter().take(2).collect();
    assert_eq!(
        SceneGraph::new(at_capacity, None, &limits).unwrap().len(),
        2
    );
}

#[test]
fn too_many_objects_with_default_capacity() {
    let capacity = Limits::default().capacity;
    let objects = (0..=capacity as u64)
        .map(|id| obj(id, [id as f64, 0.0, 0.0], &[]))
        .collect();
    assert_eq!(
        graph_err(objects, None),
        GraphError::TooManyObjects {
            count: capacity + 1,
            capacity
        }
    );
}

#[test]
fn duplicate_id() {
    let mut objects = three_objects();
    objects.push(obj(2, [5.0, 5.0, 5.0], &[0.0, 0.0]));
    assert_eq!(graph_err(objects, None), GraphError::DuplicateId { id: 2 });
}

#[test]
fn non_finite_position_nan() {
    let mut objects = three_objects();
    objects[1].position.y = f64::NAN;
    let err = graph_err(objects, None);
    assert!(
        matches!(err, GraphError::NonFinitePosition { id: 2, axis: 1, value } if value.is_nan()),
        "{err:?}"
    );
}

#[test]
fn non_finite_position_infinity() {
    for value in [f64::INFINITY, f64::NEG_INFINITY] {
        let mut objects = three_objects();
        objects[2].position.z = value;
        assert_eq!(
            graph_err(objects, None),
            GraphError::NonFinitePosition {
                id: 3,
                axis: 2,
                value
            }
        );
    }
}

#[test]
fn absurd_position() {
    let limits = Limits::default();
    let mut objects = three_objects();
    objects[0].position.x = -2.0 * limits.max_abs_coordinate;
    assert_eq!(
        graph_err(objects, None),
        GraphError::AbsurdPosition {
            id: 1,
            axis: 0,
            value: -2.0 * limits.max_abs_coordinate,
            limit: limits.max_abs_coordinate,
        }
    );
}

#[test]
fn a_stated_position_error_must_be_finite_and_non_negative() {
    for value in [-0.1, f64::NAN, f64::INFINITY] {
        let mut objects = three_objects();
        objects[1].position_sigma[2] = value;
        match graph_err(objects, None) {
            GraphError::BadPositionSigma {
                id: 2,
                axis: 2,
                value: v,
            } => {
                assert!(v.is_nan() && value.is_nan() || v == value, "{v}")
            }
            other => panic!("{value}: {other:?}"),
        }
    }
    let objects: Vec<_> = three_objects()
        .into_iter()
        .map(|o| o.with_sigma([0.0, 0.02, 0.5]))
        .collect();
    assert_eq!(
        valid_graph(objects).objects()[0].position_sigma,
        [0.0, 0.02, 0.5]
    );
}

#[test]
fn position_at_the_limit_is_accepted() {
    let limit = Limits::default().max_abs_coordinate;
    let graph = valid_graph(vec![obj(1, [limit, -limit, 0.0], &[])]);
    assert_eq!(graph.objects()[0].position.x, limit);
}

#[test]
fn absurd_position_uses_the_given_limit() {
    let limits = Limits {
        max_abs_coordinate: 10.0,
        ..Limits::default()
    };
    let err = SceneGraph::new(vec![obj(9, [0.0, 10.5, 0.0], &[])], None, &limits).unwrap_err();
    assert_eq!(
        err,
        GraphError::AbsurdPosition {
            id: 9,
            axis: 1,
            value: 10.5,
            limit: 10.0,
        }
    );
}

#[test]
fn non_finite_feature() {
    let mut objects = three_objects();
    objects[1].feature[1] = f32::NAN;
    let err = graph_err(objects, None);
    assert!(
        matches!(err, GraphError::NonFiniteFeature { id: 2, index: 1, value } if value.is_nan()),
        "{err:?}"
    );

    let mut objects = three_objects();
    objects[0].feature[0] = f32::NEG_INFINITY;
    assert_eq!(
        graph_err(objects, None),
        GraphError::NonFiniteFeature {
            id: 1,
            index: 0,
            value: f32::NEG_INFINITY
        }
    );
}

#[test]
fn feature_dim_mismatch() {
    let mut objects = three_objects();
    objects[2].feature.push(0.25);
    assert_eq!(
        graph_err(objects, None),
        GraphError::FeatureDimMismatch {
            id: 3,
            expected: 2,
            found: 3
        }
    );

    // An object without a feature among objects with features.
    let mut objects = three_objects();
    objects[1].feature.clear();
    assert_eq!(
        graph_err(objects, None),
        GraphError::FeatureDimMismatch {
            id: 2,
            expected: 2,
            found: 0
        }
    );
}

#[test]
fn unknown_edge_endpoint() {
    assert_eq!(
        graph_err(three_objects(), Some(vec![[1, 2], [2, 99]])),
        GraphError::UnknownEdgeEndpoint {
            a: 2,
            b: 99,
            unknown: 99
        }
    );
    assert_eq!(
        graph_err(three_objects(), Some(vec![[42, 3]])),
        GraphError::UnknownEdgeEndpoint {
            a: 42,
            b: 3,
            unknown: 42
        }
    );
}

#[test]
fn self_loop() {
    assert_eq!(
        graph_err(three_objects(), Some(vec![[1, 2], [3, 3]])),
        GraphError::SelfLoop { id: 3 }
    );
}

#[test]
fn graph_errors_display_their_fields() {
    let text = GraphError::NonFinitePosition {
        id: 17,
        axis: 2,
        value: f64::INFINITY,
    }
    .to_string();
    assert!(
        text.contains("17") && text.contains("position[2]") && text.contains("inf"),
        "{text}"
    );
    let text = GraphError::UnknownEdgeEndpoint {
        a: 4,
        b: 5,
        unknown: 5,
    }
    .to_string();
    assert!(text.contains("[4, 5]") && text.contains("id 5"), "{text}");
}

// ----------------------------------------------------------------- pairs

fn robot() -> SceneGraph {
    valid_graph(vec![
        obj(10, [0.0, 0.0, 1.0], &[1.0, 0.0]),
        obj(11, [0.5, 0.0, 1.0], &[0.0, 1.0]),
        obj(12, [0.0, 0.5, 1.0], &[0.5, 0.5]),
    ])
}

fn human() -> SceneGraph {
    valid_graph(three_objects())
}

fn pair_err(ground_truth: Vec<(u64, u64)>) -> PairError {
    ScenePair::new("scene".to_owned(), robot(), human(), ground_truth)
        .expect_err("pair should be refused")
}

#[test]
fn valid_pair_is_accepted() {
    let pair =
        ScenePair::new("table".to_owned(), robot(), human(), vec![(1, 10), (3, 12)]).unwrap();
    assert_eq!(pair.name, "table");
    assert_eq!(pair.robot, robot());
    assert_eq!(pair.human, human());
    assert_eq!(pair.ground_truth, vec![(1, 10), (3, 12)]);
}

#[test]
fn pair_graph_error_names_the_side() {
    for side in [Side::Robot, Side::Human] {
        let graph_error = SceneGraph::new(vec![], None, &Limits::default()).unwrap_err();
        let err = ScenePair::graph_error(side)(graph_error);
        assert_eq!(
            err,
            PairError::Graph {
                side,
                source: GraphError::Empty
            }
        );
        assert_eq!(err.to_string(), format!("{side} graph"));
        let cause = std::error::Error::source(&err).expect("the graph error");
        assert_eq!(cause.to_string(), GraphError::Empty.to_string());
    }
    assert_eq!(Side::Robot.to_string(), "robot");
    assert_eq!(Side::Human.to_string(), "human");
}

#[test]
fn feature_dims_differ() {
    let robot = valid_graph(vec![obj(10, [0.0; 3], &[1.0, 2.0, 3.0])]);
    let err = ScenePair::new("s".to_owned(), robot, human(), vec![]).unwrap_err();
    assert_eq!(err, PairError::FeatureDimsDiffer { human: 2, robot: 3 });

    // A view without features against a view with them is also a mismatch.
    let robot = valid_graph(vec![obj(10, [0.0; 3], &[])]);
    let err = ScenePair::new("s".to_owned(), robot, human(), vec![]).unwrap_err();
    assert_eq!(err, PairError::FeatureDimsDiffer { human: 2, robot: 0 });
}

#[test]
fn feature_dims_of_an_empty_graph_do_not_matter() {
    let limits = Limits {
        require_objects: false,
        ..Limits::default()
    };
    let empty = SceneGraph::new(vec![], None, &limits).unwrap();
    let pair = ScenePair::new("s".to_owned(), empty.clone(), human(), vec![]).unwrap();
    assert!(pair.robot.is_empty());
    let pair = ScenePair::new("s".to_owned(), robot(), empty, vec![]).unwrap();
    assert!(pair.human.is_empty());
}

#[test]
fn unknown_ground_truth_id_human() {
    assert_eq!(
        pair_err(vec![(1, 10), (4, 11)]),
        PairError::UnknownGroundTruthId {
            index: 1,
            side: Side::Human,
            id: 4
        }
    );
    // A robot id used as a human id is unknown: the id spaces are unrelated.
    assert_eq!(
        pair_err(vec![(10, 10)]),
        PairError::UnknownGroundTruthId {
            index: 0,
            side: Side::Human,
            id: 10
        }
    );
}

#[test]
fn unknown_ground_truth_id_robot() {
    assert_eq!(
        pair_err(vec![(1, 10), (2, 11), (3, 2)]),
        PairError::UnknownGroundTruthId {
            index: 2,
            side: Side::Robot,
            id: 2
        }
    );
}

#[test]
fn ground_truth_not_one_to_one_human() {
    assert_eq!(
        pair_err(vec![(1, 10), (2, 11), (1, 12)]),
        PairError::GroundTruthNotOneToOne {
            index: 2,
            side: Side::Human,
            id: 1
        }
    );
}

#[test]
fn ground_truth_not_one_to_one_robot() {
    assert_eq!(
        pair_err(vec![(1, 11), (2, 11)]),
        PairError::GroundTruthNotOneToOne {
            index: 1,
            side: Side::Robot,
            id: 11
        }
    );
}

#[test]
fn repeated_ground_truth_pair_is_not_one_to_one() {
    assert_eq!(
        pair_err(vec![(2, 12), (2, 12)]),
        PairError::GroundTruthNotOneToOne {
            index: 1,
            side: Side::Human,
            id: 2
        }
    );
}

#[test]
fn pair_errors_display_their_fields() {
    let text = PairError::UnknownGroundTruthId {
        index: 3,
        side: Side::Robot,
        id: 99,
    }
    .to_string();
    assert!(
        text.contains("ground_truth[3]") && text.contains("robot object id 99"),
        "{text}"
    );
    let err = PairError::Graph {
        side: Side::Human,
        source: GraphError::DuplicateId { id: 5 },
    };
    assert_eq!(err.to_string(), "human graph");
    let cause = std::error::Error::source(&err).expect("the graph error");
    assert!(cause.to_string().contains("id 5"), "{cause}");
}

/// `PairError::Graph` arises where a pair is built from raw views: reading a
/// dataset line. Each side's defect must be reported with that side.
#[test]
fn pair_graph_error_from_a_dataset_line_names_the_side() {
    use vref_scene::{DatasetError, DatasetReader};

    let good = r#"{"objects":[{"id":1,"position":[0,0,0]}]}"#;
    let dup = r#"{"objects":[{"id":1,"position":[0,0,0]},{"id":1,"position":[1,0,0]}]}"#;
    for (side, robot, human) in [(Side::Robot, dup, good), (Side::Human, good, dup)] {
        let line = format!(r#"{{"name":"n","robot":{robot},"human":{human},"ground_truth":[]}}"#);
        let mut reader = DatasetReader::new(line.as_bytes(), Limits::default());
        let err = reader.next().expect("one item").expect_err("invalid line");
        match err {
            DatasetError::Invalid { line, name, source } => {
                assert_eq!(line, 1);
                assert_eq!(name, "n");
                assert_eq!(
                    source,
                    PairError::Graph {
                        side,
                        source: GraphError::DuplicateId { id: 1 }
                    }
                );
            }
            other => panic!("expected Invalid, got {other:?}"),
        }
        assert!(reader.next().is_none());
    }
}

#[test]
fn raised_ids_keep_the_objects_and_their_edges() {
    let objects = vec![
        obj(1, [0.0, 0.0, 1.0], &[1.0, 0.0]),
        obj(2, [0.1, 0.0, 1.0], &[0.0, 1.0]),
        obj(3, [0.0, 0.1, 1.0], &[0.5, 0.5]),
    ];
    let graph = SceneGraph::new(objects, Some(vec![[1, 3], [2, 3]]), &Limits::default()).unwrap();
    let raised = graph.with_ids_raised(100, &Limits::default()).unwrap();
    let ids: Vec<u64> = raised.objects().iter().map(|o| o.id).collect();
    assert_eq!(ids, [101, 102, 103]);
    for (a, b) in graph.objects().iter().zip(raised.objects()) {
        assert_eq!((a.position, &a.feature), (b.position, &b.feature));
    }
    assert_eq!(raised.edge_ids(), Some(vec![[101, 103], [102, 103]]));
    let unlinked = SceneGraph::new(vec![obj(4, [0.0, 0.0, 1.0], &[])], None, &Limits::default())
        .unwrap()
        .with_ids_raised(1, &Limits::default())
        .unwrap();
    assert_eq!(unlinked.edge_ids(), None);
}

#[test]
fn raising_an_id_beyond_the_largest_is_refused() {
    let graph = SceneGraph::new(
        vec![
            obj(7, [0.0, 0.0, 1.0], &[]),
            obj(u64::MAX - 1, [0.1, 0.0, 1.0], &[]),
        ],
        None,
        &Limits::default(),
    )
    .unwrap();
    assert_eq!(
        graph.with_ids_raised(2, &Limits::default()).unwrap_err(),
        GraphError::IdOverflow {
            id: u64::MAX - 1,
            offset: 2
        }
    );
    assert!(
        GraphError::IdOverflow { id: 9, offset: 4 }
            .to_string()
            .contains("object id 9 raised by 4")
    );
}
