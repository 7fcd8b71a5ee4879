#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use vref_scene::{GraphError, Limits, Side};
use vref_wire::{WireError, validate_snapshot};

use super::*;

fn target(side: Side) -> Target {
    Target {
        side,
        session: 42,
        capacity: Limits::default().capacity,
        timestamp_ns: 1,
    }
}

/// What the matcher's wire validation says about each message of a run.
fn verdicts(kind: Kind, side: Side) -> Vec<Result<u64, WireError>> {
    let limits = Limits::default();
    messages(kind, &target(side), 0)
        .into_iter()
        .map(|m| match m {
            Message::Snapshot { header, entries } => {
                validate_snapshot(&header, &entries, side, &limits).map(|s| s.sequence)
            }
            Message::Ray(ray) => ray.validate().map(|r| r.sequence),
        })
        .collect()
}

fn single_error(kind: Kind) -> WireError {
    match verdicts(kind, Side::Robot).as_slice() {
        [Err(e)] => e.clone(),
        other => panic!("{kind}: {other:?}"),
    }
}

#[test]
fn valid_snapshots_pass_on_both_sides() {
    for side in [Side::Robot, Side::Human] {
        assert_eq!(verdicts(Kind::Valid, side), vec![Ok(1)]);
    }
}

#[test]
fn each_malformed_kind_fails_validation_for_its_own_defect() {
    assert!(matches!(
        single_error(Kind::Nan),
        WireError::Graph(GraphError::NonFinitePosition { value, .. }) if value.is_nan()
    ));
    assert!(matches!(
        single_error(Kind::Inf),
        WireError::Graph(GraphError::NonFinitePosition { value, .. }) if value.is_infinite()
    ));
    assert!(matches!(
        single_error(Kind::Huge),
        WireError::Graph(GraphError::AbsurdPosition { .. })
    ));
    assert!(matches!(
        single_error(Kind::CountOverSlice),
        WireError::CountExceedsSlice {
            count: 11,
            slice: 6
        }
    ));
    assert!(matches!(
        single_error(Kind::CountOverCapacity),
        WireError::Graph(GraphError::TooManyObjects {
            count: 257,
            capacity: 256
        })
    ));
    assert!(matches!(
        single_error(Kind::FeatureDimTooLarge),
        WireError::FeatureDimTooLarge { dim: 65, .. }
    ));
    assert!(matches!(
        single_error(Kind::DuplicateIds),
        WireError::Graph(GraphError::DuplicateId { .. })
    ));
    assert!(matches!(
        single_error(Kind::ZeroRay),
        WireError::ZeroRayDirection
    ));
    assert!(matches!(
        single_error(Kind::SchemaVersion),
        WireError::SchemaVersion { .. }
    ));
    assert!(matches!(
        single_error(Kind::BadUp),
        WireError::Graph(GraphError::BadUp {
            up: [0.0, 0.0, 0.0]
        })
    ));
}

/// These two are well-formed on their own: only the matcher's memory of
/// the other side or of the session makes them wrong.
#[test]
fn stateful_kinds_are_well_formed_alone() {
    assert_eq!(
        verdicts(Kind::SequenceBackwards, Side::Human),
        vec![Ok(10), Ok(5)]
    );
    let Some(Message::Snapshot { header, entries }) =
        messages(Kind::FeatureDimOtherSide, &target(Side::Human), 0).pop()
    else {
        panic!("not a snapshot");
    };
    let snapshot = validate_snapshot(&header, &entries, Side::Human, &Limits::default()).unwrap();
    assert_eq!(snapshot.graph.feature_dim(), OTHER_FEATURE_DIM);
    assert_ne!(OTHER_FEATURE_DIM, VALID_FEATURE_DIM);
}

/// Well-formed too: only the stamp, or the session they take over, is
/// wrong, which the matcher's intake judges.
#[test]
fn stamp_and_hijack_kinds_are_well_formed_alone() {
    for kind in [Kind::FutureStamp, Kind::OldStamp] {
        assert_eq!(verdicts(kind, Side::Robot), vec![Ok(1)], "{kind}");
    }
    assert_eq!(
        verdicts(Kind::HijackSequence, Side::Robot),
        vec![Ok(u64::MAX)]
    );
    assert_eq!(verdicts(Kind::HijackRay, Side::Robot), vec![Ok(u64::MAX)]);
    let stamps: Vec<u64> = [Kind::FutureStamp, Kind::OldStamp]
        .into_iter()
        .flat_map(|k| messages(k, &target(Side::Robot), 0))
        .filter_map(|m| match m {
            Message::Snapshot { header, .. } => Some(header.timestamp_ns),
            Message::Ray(_) => None,
        })
        .collect();
    assert_eq!(stamps, vec![1 + AN_HOUR_NS, 0]);
    assert!(Kind::HijackRay.is_ray() && Kind::HijackRay.hijacks());
}

#[test]
fn later_rounds_move_sequences_forward() {
    let sequences = |round| -> Vec<u64> {
        messages(Kind::SequenceBackwards, &target(Side::Robot), round)
            .into_iter()
            .filter_map(|m| match m {
                Message::Snapshot { header, .. } => Some(header.sequence),
                Message::Ray(_) => None,
            })
            .collect()
    };
    assert_eq!(sequences(0), vec![10, 5]);
    assert_eq!(sequences(1), vec![20, 15]);
    assert!(sequences(1)[0] > sequences(0)[0]);
}

#[test]
fn kinds_parse_from_their_names_and_unknown_ones_list_all() {
    for kind in Kind::ALL {
        assert_eq!(kind.name().parse::<Kind>(), Ok(kind));
    }
    let error = "nope".parse::<Kind>().unwrap_err().to_string();
    assert!(error.contains("`nope`"), "{error}");
    for kind in Kind::ALL {
        assert!(error.contains(kind.name()), "{error}");
    }
}
