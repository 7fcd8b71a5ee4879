//! A snapshot written in place into loaned shared memory arrives intact
//! and validates, through real iceoryx2 services isolated by root path and
//! prefix.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use iceoryx2::prelude::*;
use vref_scene::{Limits, Side};
use vref_wire::ipc::{IpcSettings, create_node};
use vref_wire::{
    FRAME_NAME_LEN, MAX_FEATURE_DIM, ObjectEntry, SCHEMA_VERSION, SideCode, SnapshotHeader,
    validate_snapshot,
};

#[test]
fn snapshot_round_trip_through_shared_memory() {
    let root = tempfile::tempdir().unwrap();
    let settings = IpcSettings {
        root_path: Some(root.path().to_owned()),
        prefix: format!("vref_wire_{}_", std::process::id()),
        ..IpcSettings::default()
    };
    let node = create_node(&settings, "wire-test").unwrap();
    let service = node
        .service_builder(&"vref/test/robot/snapshot".try_into().unwrap())
        .publish_subscribe::<[ObjectEntry]>()
        .user_header::<SnapshotHeader>()
        .history_size(1)
        .subscriber_max_buffer_size(1)
        .enable_safe_overflow(true)
        .open_or_create()
        .unwrap();
    let publisher = service
        .publisher_builder()
        .initial_max_slice_len(2)
        .allocation_strategy(AllocationStrategy::PowerOfTwo)
        .create()
        .unwrap();
    let subscriber = service.subscriber_builder().create().unwrap();

    let objects: Vec<ObjectEntry> = (0..5)
        .map(|k| {
            let mut feature = [0.0; MAX_FEATURE_DIM];
            feature[..3].copy_from_slice(&[1.0, k as f32, 0.5]);
            ObjectEntry {
                track_id: 40 + k,
                position: [k as f32 * 0.1, 0.2, 1.5],
                position_sigma: [0.01; 3],
                feature,
            }
        })
        .collect();
    let mut frame_name = [0u8; FRAME_NAME_LEN];
    frame_name[..5].copy_from_slice(b"robot");
    // Five objects exceed the initial slice length of two: the
    // power-of-two strategy must grow the segment.
    let mut sample = publisher.loan_slice_uninit(objects.len()).unwrap();
    *sample.user_header_mut() = SnapshotHeader {
        session: 11,
        sequence: 3,
        timestamp_ns: 99,
        schema_version: SCHEMA_VERSION,
        side: SideCode::Robot as u32,
        object_count: 5,
        feature_dim: 3,
        frame_name,
        up: [0.0; 3],
        flags: 0,
    };
    sample.write_from_fn(|i| objects[i]).send().unwrap();

    let received = subscriber.receive().unwrap().expect("a sample");
    assert_eq!(received.payload(), &objects[..]);
    let snapshot = validate_snapshot(
        received.user_header(),
        received.payload(),
        Side::Robot,
        &Limits::default(),
    )
    .unwrap();
    assert_eq!(snapshot.sequence, 3);
    assert_eq!(snapshot.frame_name, "robot");
    assert_eq!(snapshot.graph.len(), 5);
    assert_eq!(snapshot.graph.index_of(42), Some(2));
    assert_eq!(snapshot.graph.objects()[4].feature, vec![1.0, 4.0, 0.5]);
}

/// The feeds' publisher writes the graph's up vector, or says there is
/// none, and validation of what arrives gives it back (unit length).
#[test]
fn a_published_up_vector_arrives_and_a_missing_one_stays_missing() {
    use vref_scene::{SceneGraph, SceneObject};
    use vref_wire::ipc::{SnapshotPublisher, open_snapshot};
    use vref_wire::wire_up;

    let root = tempfile::tempdir().unwrap();
    let settings = IpcSettings {
        root_path: Some(root.path().to_path_buf()),
        prefix: format!("vref_up_{}_", std::process::id()),
        namespace: "vref_test_up".to_owned(),
        ..IpcSettings::default()
    };
    let node = create_node(&settings, "up-test").unwrap();
    let mut publisher =
        SnapshotPublisher::new(&node, &settings, Side::Human, "headset_camera").unwrap();
    let (data, _event) = open_snapshot(&node, &settings, Side::Human).unwrap();
    let subscriber = data.subscriber_builder().create().unwrap();

    let limits = Limits::default();
    let objects = (0..3)
        .map(|k| SceneObject::new(k, [0.1 * k as f64, 0.0, 1.0], vec![1.0, 0.5]))
        .collect();
    let graph = SceneGraph::new(objects, None, &limits).unwrap();
    let tilted = graph.clone().with_up(Some([0.1, -1.0, 0.2])).unwrap();
    let entries: Vec<ObjectEntry> = graph
        .objects()
        .iter()
        .map(|o| {
            let mut feature = [0.0; MAX_FEATURE_DIM];
            feature[..2].copy_from_slice(&[1.0, 0.5]);
            ObjectEntry {
                track_id: o.id,
                position: o.position.coords.map(|v| v as f32).into(),
                position_sigma: [0.0; 3],
                feature,
            }
        })
        .collect();

    let mut receive = |g: &SceneGraph| {
        publisher
            .publish(entries.len(), 2, wire_up(g), 7, |i| entries[i])
            .unwrap();
        let sample = subscriber.receive().unwrap().expect("a sample");
        validate_snapshot(sample.user_header(), sample.payload(), Side::Human, &limits).unwrap()
    };
    let got = receive(&tilted).graph.up().expect("the up vector");
    let sent = tilted.up().unwrap();
    // Single precision on the wire.
    assert!((got - sent).norm() < 1e-6, "{got} vs {sent}");
    assert!((got.norm() - 1.0).abs() < 1e-12);
    assert_eq!(receive(&graph).graph.up(), None);
}

#[test]
fn nodes_are_created_from_the_shipped_iceoryx2_config_with_vref_overrides() {
    let root = tempfile::tempdir().unwrap();
    let shipped =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../config/iceoryx2.toml");
    let settings = IpcSettings {
        iceoryx2_config: Some(shipped),
        root_path: Some(root.path().to_owned()),
        prefix: format!("vref_cfg_{}_", std::process::id()),
        ..IpcSettings::default()
    };
    let node = create_node(&settings, "config-test").unwrap();
    assert!(node.config().global.node.cleanup_dead_nodes_on_creation);
    assert_eq!(
        node.config().global.prefix.as_bytes(),
        settings.prefix.as_bytes()
    );
    drop(node);

    let missing = IpcSettings {
        iceoryx2_config: Some("/nonexistent/iceoryx2.toml".into()),
        ..settings
    };
    let err = create_node(&missing, "config-test").unwrap_err();
    assert!(
        err.to_string().contains("/nonexistent/iceoryx2.toml"),
        "{err}"
    );
}

#[test]
fn a_decision_round_trips_through_its_service() {
    use vref_wire::ipc::{Decision, DecisionPublisher, DecisionReader};
    use vref_wire::{AnswerStatus, DecisionEntry, DecisionHeader};

    let root = tempfile::tempdir().unwrap();
    let settings = IpcSettings {
        root_path: Some(root.path().to_path_buf()),
        prefix: format!("vref_dec_{}_", std::process::id()),
        namespace: "vref_test_decision".to_owned(),
        initial_objects: 2,
        ..IpcSettings::default()
    };
    let node = create_node(&settings, "decision-publisher").unwrap();
    let mut publisher = DecisionPublisher::new(&node, &settings).unwrap();
    let reader = DecisionReader::connect(&settings, "decision-reader").unwrap();
    assert!(reader.latest().unwrap().is_none());

    let entries: Vec<DecisionEntry> = (0..5)
        .map(|k| DecisionEntry {
            human_track_id: k,
            robot_track_id: 100 + k,
            confidence: 0.9,
            status: AnswerStatus::Ok as u32,
            flags: DecisionEntry::FLAG_PARTNER,
            residual: 0.0,
        })
        .collect();
    let mut header = DecisionHeader {
        robot_sequence: 7,
        human_sequence: 9,
        solve_index: 3,
        flags: DecisionHeader::FLAG_MOTION,
        ..DecisionHeader::default()
    };
    header.method[..5].copy_from_slice(b"rigid");
    // Five entries exceed the initial slice length of two.
    publisher
        .publish(header, entries.len(), |i| entries[i])
        .unwrap();
    let got: Decision = reader.latest().unwrap().expect("a decision").unwrap();
    assert_eq!(got.entries, entries);
    assert_eq!(got.header.pair_count, 5);
    assert_eq!(got.header.robot_sequence, 7);
    assert_eq!(got.method(), "rigid");
    assert!(reader.latest().unwrap().is_none(), "nothing new");
}
