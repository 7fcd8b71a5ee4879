#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use proptest::prelude::*;
use vref_scene::{GraphError, Limits, Side};
use vref_wire::{
    FRAME_NAME_LEN, MAX_FEATURE_DIM, ObjectEntry, PointingRay, SCHEMA_VERSION, SideCode,
    SnapshotHeader, WireError, validate_snapshot,
};

fn header(count: u32, dim: u32) -> SnapshotHeader {
    let mut frame_name = [0u8; FRAME_NAME_LEN];
    frame_name[..12].copy_from_slice(b"robot_camera");
    SnapshotHeader {
        session: 11,
        sequence: 7,
        timestamp_ns: 1_000,
        schema_version: SCHEMA_VERSION,
        side: SideCode::Robot as u32,
        object_count: count,
        feature_dim: dim,
        frame_name,
        up: [0.0; 3],
        flags: 0,
    }
}

fn entry(id: u64, x: f32) -> ObjectEntry {
    let mut feature = [0.0; MAX_FEATURE_DIM];
    feature[0] = 1.0;
    feature[1] = x;
    ObjectEntry {
        track_id: id,
        position: [x, 0.5, 1.0],
        position_sigma: [0.01; 3],
        feature,
    }
}

fn entries() -> Vec<ObjectEntry> {
    vec![entry(10, 0.1), entry(11, 0.2), entry(12, 0.3)]
}

fn check(h: SnapshotHeader, e: &[ObjectEntry]) -> Result<vref_wire::ValidSnapshot, WireError> {
    validate_snapshot(&h, e, Side::Robot, &Limits::default())
}

#[test]
fn a_good_snapshot_becomes_a_scene_graph() {
    let s = check(header(3, 2), &entries()).unwrap();
    assert_eq!(
        (s.side, s.sequence, s.timestamp_ns),
        (Side::Robot, 7, 1_000)
    );
    assert_eq!(s.frame_name, "robot_camera");
    assert_eq!(s.graph.len(), 3);
    assert_eq!(s.graph.feature_dim(), 2);
    assert_eq!(s.graph.objects()[1].feature, vec![1.0, 0.2]);
    assert_eq!(s.graph.objects()[2].position.x, f64::from(0.3f32));
    assert_eq!(s.graph.objects()[0].position_sigma, [f64::from(0.01f32); 3]);
}

#[test]
fn a_longer_slice_than_the_count_uses_only_the_count() {
    let s = check(header(2, 2), &entries()).unwrap();
    assert_eq!(s.graph.len(), 2);
}

#[test]
fn every_defect_has_its_error() {
    let e = entries();
    let mut h = header(3, 2);
    h.schema_version = 99;
    assert_eq!(
        check(h, &e).unwrap_err(),
        WireError::SchemaVersion {
            found: 99,
            expected: SCHEMA_VERSION
        }
    );

    let mut h = header(3, 2);
    h.side = 5;
    assert_eq!(check(h, &e).unwrap_err(), WireError::UnknownSide(5));

    let mut h = header(3, 2);
    h.side = SideCode::Human as u32;
    assert_eq!(
        check(h, &e).unwrap_err(),
        WireError::WrongSide {
            expected: Side::Robot,
            found: Side::Human
        }
    );

    assert_eq!(
        check(header(4, 2), &e).unwrap_err(),
        WireError::CountExceedsSlice { count: 4, slice: 3 }
    );
    assert_eq!(
        check(header(3, 65), &e).unwrap_err(),
        WireError::FeatureDimTooLarge {
            dim: 65,
            max: MAX_FEATURE_DIM
        }
    );

    let mut h = header(3, 2);
    h.frame_name[0] = 0xff;
    assert_eq!(check(h, &e).unwrap_err(), WireError::FrameNameNotUtf8);

    let small = Limits {
        capacity: 2,
        ..Limits::default()
    };
    assert_eq!(
        validate_snapshot(&header(3, 2), &e, Side::Robot, &small).unwrap_err(),
        WireError::Graph(GraphError::TooManyObjects {
            count: 3,
            capacity: 2
        })
    );

    let mut bad = entries();
    bad[1].position[2] = f32::NAN;
    assert!(matches!(
        check(header(3, 2), &bad),
        Err(WireError::Graph(GraphError::NonFinitePosition {
            id: 11,
            axis: 2,
            ..
        }))
    ));

    let mut bad = entries();
    bad[0].position[0] = 1e30;
    assert!(matches!(
        check(header(3, 2), &bad),
        Err(WireError::Graph(GraphError::AbsurdPosition { id: 10, .. }))
    ));

    let mut bad = entries();
    bad[2].feature[1] = f32::INFINITY;
    assert!(matches!(
        check(header(3, 2), &bad),
        Err(WireError::Graph(GraphError::NonFiniteFeature {
            id: 12,
            index: 1,
            ..
        }))
    ));

    let mut bad = entries();
    bad[2].track_id = 10;
    assert_eq!(
        check(header(3, 2), &bad).unwrap_err(),
        WireError::Graph(GraphError::DuplicateId { id: 10 })
    );

    let mut bad = entries();
    bad[0].position_sigma[1] = -1.0;
    assert_eq!(
        check(header(3, 2), &bad).unwrap_err(),
        WireError::BadUncertainty {
            id: 10,
            value: -1.0
        }
    );

    assert_eq!(
        check(header(0, 2), &e).unwrap_err(),
        WireError::Graph(GraphError::Empty)
    );
}

#[test]
fn an_up_vector_arrives_at_unit_length_only_where_flagged() {
    let mut h = header(3, 2);
    h.set_up(Some([0.0, -3.0, 4.0]));
    let up = check(h, &entries())
        .unwrap()
        .graph
        .up()
        .expect("an up vector");
    assert!(
        (up - nalgebra::Vector3::new(0.0, -0.6, 0.8)).norm() < 1e-7,
        "{up}"
    );

    // Without the flag the field means nothing, whatever it holds.
    let mut h = header(3, 2);
    h.up = [f32::NAN, 0.0, 0.0];
    assert_eq!(check(h, &entries()).unwrap().graph.up(), None);
    assert_eq!(check(header(3, 2), &entries()).unwrap().graph.up(), None);
}

#[test]
fn an_up_vector_that_is_no_direction_is_refused() {
    for bad in [
        [0.0, 0.0, 0.0],
        [0.0, 1e-9, 0.0],
        [f32::NAN, 1.0, 0.0],
        [0.0, f32::INFINITY, 0.0],
        [0.0, 0.0, f32::NEG_INFINITY],
    ] {
        let mut h = header(3, 2);
        h.set_up(Some(bad));
        match check(h, &entries()) {
            Err(WireError::Graph(GraphError::BadUp { up })) => {
                let sent = bad.map(f64::from);
                assert!(
                    up.iter()
                        .zip(&sent)
                        .all(|(a, b)| a == b || (a.is_nan() && b.is_nan())),
                    "{up:?} is not {sent:?}"
                );
            }
            other => panic!("{bad:?}: {other:?}"),
        }
    }
}

fn ray() -> PointingRay {
    PointingRay {
        session: 11,
        sequence: 1,
        timestamp_ns: 5,
        origin: [0.0, 0.0, 0.0],
        direction: [0.0, 0.0, 2.0],
        cone_half_angle: 0.1,
        confidence: 0.9,
        schema_version: SCHEMA_VERSION,
        reserved: 0,
    }
}

#[test]
fn rays_are_checked_and_normalised() {
    let r = ray().validate().unwrap();
    assert_eq!(
        r.direction.into_inner(),
        nalgebra::Vector3::new(0.0, 0.0, 1.0)
    );
    type Spoil = fn(&mut PointingRay);
    let spoil: [(Spoil, WireError); 6] = [
        (|r| r.direction = [0.0; 3], WireError::ZeroRayDirection),
        (
            |r| r.origin[1] = f32::NAN,
            WireError::NonFiniteRay { field: "origin" },
        ),
        (
            |r| r.direction[0] = f32::INFINITY,
            WireError::NonFiniteRay { field: "direction" },
        ),
        (|r| r.cone_half_angle = 0.0, WireError::BadConeAngle(0.0)),
        (|r| r.confidence = 1.5, WireError::BadConfidence(1.5)),
        (
            |r| r.schema_version = 0,
            WireError::SchemaVersion {
                found: 0,
                expected: SCHEMA_VERSION,
            },
        ),
    ];
    for (f, expected) in spoil {
        let mut r = ray();
        f(&mut r);
        assert_eq!(r.validate().unwrap_err(), expected);
    }
}

proptest! {
    /// Arbitrary bytes in every field never panic the validator.
    #[test]
    fn arbitrary_snapshots_never_panic(
        count in any::<u32>(), dim in any::<u32>(), side in any::<u32>(), version in 0u32..3,
        ids in prop::collection::vec(any::<u64>(), 0..6),
        values in prop::collection::vec(any::<f32>(), 0..12),
    ) {
        let mut h = header(count, dim);
        h.side = side;
        h.schema_version = version;
        let e: Vec<ObjectEntry> = ids.iter().enumerate().map(|(k, &id)| {
            let mut x = entry(id, 0.0);
            x.position = [values.get(k).copied().unwrap_or(0.0), 0.0, 1.0];
            x.feature[0] = values.get(k + 6).copied().unwrap_or(1.0);
            x
        }).collect();
        let _ = check(h, &e);
    }
}
