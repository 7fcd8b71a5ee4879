#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use vref_match::{SceneScore, Summary, score_scene};

#[test]
fn all_right() {
    let s = score_scene(&[1, 2], &[(1, 10), (2, 20)], &[(1, 10), (2, 20)]);
    assert_eq!(
        s,
        SceneScore {
            accuracy: 1.0,
            precision: 1.0,
            recall: 1.0
        }
    );
}

#[test]
fn unpartnered_object_left_unmatched_counts_as_right() {
    // Object 3 has no partner and none is predicted: right.
    let s = score_scene(&[1, 2, 3], &[(1, 10), (2, 30)], &[(1, 10), (2, 20)]);
    assert_eq!(s.accuracy, 2.0 / 3.0);
    assert_eq!(s.precision, 0.5);
    assert_eq!(s.recall, 0.5);
}

#[test]
fn forcing_a_partner_on_an_unpartnered_object_is_wrong() {
    let s = score_scene(&[1, 2], &[(1, 10), (2, 20)], &[(1, 10)]);
    assert_eq!(s.accuracy, 0.5);
    assert_eq!(s.precision, 0.5);
    assert_eq!(s.recall, 1.0);
}

#[test]
fn empty_prediction_and_empty_truth() {
    assert_eq!(
        score_scene(&[1], &[], &[]),
        SceneScore {
            accuracy: 1.0,
            precision: 1.0,
            recall: 1.0
        }
    );
    let s = score_scene(&[1], &[], &[(1, 10)]);
    assert_eq!(
        s,
        SceneScore {
            accuracy: 0.0,
            precision: 0.0,
            recall: 0.0
        }
    );
}

#[test]
fn summary_is_mean_and_population_std() {
    let a = SceneScore {
        accuracy: 1.0,
        precision: 1.0,
        recall: 0.5,
    };
    let b = SceneScore {
        accuracy: 0.0,
        precision: 0.5,
        recall: 0.5,
    };
    let s = Summary::from_scores(&[a, b]);
    assert_eq!(s.scenes, 2);
    assert_eq!(s.accuracy.mean, 0.5);
    assert_eq!(s.accuracy.std, 0.5);
    assert_eq!(s.precision.mean, 0.75);
    assert_eq!(s.recall.std, 0.0);
}
