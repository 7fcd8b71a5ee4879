#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! A live world is a pure function of its inputs and the time: objects
//! drift smoothly, leave and come back; the ground truth and the gestures
//! agree with what the cameras detect.

use std::collections::HashMap;

use vref_scene::Side;
use vref_sim::{ConfigError, Dynamics, LiveView, LiveWorld, Preset};

/// Wall-clock seconds of a day in 2024: the feeds run at times this large.
const T0: f64 = 1.72e9;
const FRAME: f64 = 1.0 / 30.0;

fn world(preset: Preset, seed: u64) -> LiveWorld {
    LiveWorld::new(preset.config(), Dynamics::default(), seed, None).unwrap()
}

fn field_of(error: ConfigError) -> String {
    match error {
        ConfigError::Invalid { field, .. } => field,
        other => panic!("expected an invalid field, got {other}"),
    }
}

#[test]
fn equal_inputs_give_identical_worlds() {
    for preset in Preset::ALL {
        let (a, b) = (world(preset, 7), world(preset, 7));
        for (k, t) in [T0, T0 + 13.37, T0 + 600.5, 0.0, -42.0]
            .into_iter()
            .enumerate()
        {
            let frame = 1000 + k as u64;
            for side in [Side::Robot, Side::Human] {
                assert_eq!(a.observe(side, t, frame), b.observe(side, t, frame));
            }
            assert_eq!(a.truth(t), b.truth(t));
            assert_eq!(a.gesture(t), b.gesture(t));
        }
        for k in 0..a.object_count() {
            for side in [Side::Robot, Side::Human] {
                assert_eq!(a.track_id(side, k), b.track_id(side, k));
            }
        }
        // Another seed is another world.
        let c = world(preset, 8);
        assert_ne!(
            a.observe(Side::Robot, T0, 1).objects,
            c.observe(Side::Robot, T0, 1).objects
        );
    }
}

#[test]
fn measurement_errors_are_keyed_by_frame_number() {
    let still = LiveWorld::new(Preset::Moi.config(), Dynamics::still(), 3, None).unwrap();
    for side in [Side::Robot, Side::Human] {
        // Nothing moves: the same frame number measures the same way at
        // any time, and another frame number measures differently.
        let first = still.observe(side, T0, 5);
        let later = still.observe(side, T0 + 100.0, 5);
        assert_eq!(first.objects, later.objects);
        let other = still.observe(side, T0, 6);
        assert_eq!(ids(&first), ids(&other));
        assert_ne!(first.objects, other.objects);
    }
}

fn ids(view: &LiveView) -> Vec<u64> {
    view.objects.iter().map(|o| o.id).collect()
}

#[test]
fn track_ids_are_stable_and_differ_between_views() {
    let w = world(Preset::Moi, 11);
    for side in [Side::Robot, Side::Human] {
        let mut all: Vec<u64> = (0..w.object_count())
            .map(|k| w.track_id(side, k).unwrap())
            .collect();
        all.sort_unstable();
        all.dedup();
        assert_eq!(all.len(), w.object_count(), "{side}: ids repeat");
        for t in [T0, T0 + 77.0, T0 + 300.0] {
            for o in w.observe(side, t, 0).objects {
                assert_eq!(w.track_id(side, o.object), Some(o.id));
            }
        }
    }
    let same = (0..w.object_count())
        .filter(|&k| w.track_id(Side::Robot, k) == w.track_id(Side::Human, k))
        .count();
    assert_eq!(same, 0);
    assert_eq!(w.track_id(Side::Robot, w.object_count()), None);
}

#[test]
fn positions_change_smoothly_and_objects_never_overlap() {
    for preset in Preset::ALL {
        // Without sensor noise a reported position is the object's centre,
        // so frame-to-frame changes are the world's own motion.
        let config = preset.config().noiseless();
        let min_gap = config.workspace.min_gap;
        let w = LiveWorld::new(config, Dynamics::default(), 5, None).unwrap();
        let mut largest_step: f64 = 0.0;
        let mut first: HashMap<u64, nalgebra::Point3<f64>> = HashMap::new();
        let mut largest_travel: f64 = 0.0;
        for side in [Side::Robot, Side::Human] {
            let mut previous = w.observe(side, T0, 0);
            for k in 1..=300u64 {
                let view = w.observe(side, T0 + k as f64 * FRAME, k);
                for o in &view.objects {
                    if let Some(p) = previous.objects.iter().find(|p| p.id == o.id) {
                        largest_step = largest_step.max((o.position - p.position).norm());
                    }
                    let start = *first.entry(o.id).or_insert(o.position);
                    largest_travel = largest_travel.max((o.position - start).norm());
                }
                previous = view;
            }
        }
        // Drift and head sway move a few tenths of a millimetre per frame.
        assert!(largest_step < 0.002, "{preset}: a step of {largest_step} m");
        assert!(largest_travel > 0.002, "{preset}: nothing moved in 10 s");

        for k in 0..200 {
            let t = T0 + 1.7 * k as f64;
            let present: Vec<_> = (0..w.object_count())
                .filter_map(|j| w.object(j, t))
                .collect();
            for (i, a) in present.iter().enumerate() {
                for b in &present[i + 1..] {
                    let apart = (a.centre.x - b.centre.x).hypot(a.centre.y - b.centre.y);
                    let least = a.shape.footprint_radius() + b.shape.footprint_radius() + min_gap;
                    assert!(apart >= least - 1e-9, "{preset}: objects overlap at t={t}");
                }
            }
        }
    }
}

#[test]
fn objects_leave_and_come_back() {
    let dynamics = Dynamics::default();
    let w = world(Preset::Moi, 2);
    let step = 0.5;
    let samples = (10.0 * dynamics.presence_period_s / step) as usize;
    for k in 0..w.object_count() {
        let present: Vec<bool> = (0..samples)
            .map(|s| w.object(k, T0 + s as f64 * step).is_some())
            .collect();
        let returns = present.windows(2).filter(|p| !p[0] && p[1]).count();
        assert!(
            returns >= 8,
            "object {k} came back {returns} times in 10 cycles"
        );
        let away = present.iter().filter(|&&p| !p).count() as f64 / samples as f64;
        assert!(
            (away - dynamics.absent_share).abs() < 0.03,
            "object {k} away {away} of the time"
        );
        // Consistent with the interval query.
        let s = present.iter().position(|&p| !p).unwrap();
        let t = T0 + s as f64 * step;
        assert!(w.away_during(k, t - 0.1, t + 0.1));
    }
    // Not all at once: most of the time most objects are there.
    let counts: Vec<usize> = (0..samples)
        .map(|s| {
            let t = T0 + s as f64 * step;
            (0..w.object_count())
                .filter(|&k| w.object(k, t).is_some())
                .count()
        })
        .collect();
    assert!(counts.iter().all(|&c| c + 4 >= w.object_count()));
    // And what is away is not reported.
    for s in (0..samples).step_by(37) {
        let t = T0 + s as f64 * step;
        for side in [Side::Robot, Side::Human] {
            for o in w.observe(side, t, s as u64).objects {
                assert!(w.object(o.object, t).is_some());
            }
        }
    }
}

#[test]
fn truth_pairs_exactly_the_objects_both_views_detect() {
    for preset in Preset::ALL {
        for seed in [1, 2, 3] {
            let w = world(preset, seed);
            for k in 0..40u64 {
                let t = T0 + 7.3 * k as f64;
                let robot = w.observe(Side::Robot, t, k);
                let human = w.observe(Side::Human, t, k);
                let mut expected: Vec<(u64, u64)> = human
                    .objects
                    .iter()
                    .filter_map(|h| {
                        let r = robot.objects.iter().find(|r| r.object == h.object)?;
                        Some((h.id, r.id))
                    })
                    .collect();
                expected.sort_unstable();
                assert_eq!(w.truth(t), expected, "{preset} seed {seed} t {t}");
                let detected: Vec<usize> = robot.objects.iter().map(|o| o.object).collect();
                let mut sorted = detected.clone();
                sorted.sort_unstable();
                assert_eq!(w.detected(Side::Robot, t), sorted);
            }
        }
    }
}

#[test]
fn views_are_valid_graphs_with_sane_uncertainties() {
    let w = world(Preset::Mrc, 4);
    for k in 0..20u64 {
        let t = T0 + 3.1 * k as f64;
        for side in [Side::Robot, Side::Human] {
            let view = w.observe(side, t, k);
            assert!(view.objects.windows(2).all(|p| p[0].id < p[1].id));
            let graph = view.graph(&vref_scene::Limits::default()).unwrap();
            assert_eq!(graph.len(), view.objects.len());
            assert_eq!(graph.feature_dim(), w.config().features.dim());
            for o in &view.objects {
                assert!(o.position.z > 0.0, "behind the camera");
                assert!(o.sigma.iter().all(|s| s.is_finite() && *s > 0.0));
                // Depth error dominates along the line of sight.
                assert!(o.sigma[2] >= o.sigma[0].min(o.sigma[1]));
            }
        }
    }
}

/// The human-view object a ray points at, as the matcher resolves it: the
/// smallest angle within the cone.
fn pointed_at(view: &LiveView, g: &vref_sim::Gesture) -> Option<u64> {
    let mut best: Option<(u64, f64)> = None;
    for o in &view.objects {
        let d = o.position - g.origin;
        let angle = (d.dot(&g.direction) / d.norm()).clamp(-1.0, 1.0).acos();
        if angle <= g.cone_half_angle && best.is_none_or(|(_, a)| angle < a) {
            best = Some((o.id, angle));
        }
    }
    best.map(|(id, _)| id)
}

#[test]
fn gestures_point_at_their_target() {
    let dynamics = Dynamics::default();
    let period = dynamics.gesture_period_s;
    for preset in Preset::ALL {
        for seed in [1, 2, 3] {
            let w = world(preset, seed);
            let (mut hits, mut slots) = (0, 0);
            let mut targets = Vec::new();
            for s in 0..40 {
                let start = (T0 / period).floor() * period + s as f64 * period;
                let g = w.gesture(start + 0.5 * period).unwrap();
                // One target per slot, named by its track ids.
                assert_eq!(w.gesture(start + 0.01).unwrap().target, g.target);
                assert_eq!(w.gesture(start + 0.99 * period).unwrap().target, g.target);
                assert_eq!(w.track_id(Side::Human, g.target), Some(g.human_id));
                assert_eq!(w.track_id(Side::Robot, g.target), Some(g.robot_id));
                assert!(w.object(g.target, start + 0.5 * period).is_some());
                assert!(g.cone_half_angle > 0.0 && (0.0..=1.0).contains(&g.confidence));
                targets.push(g.target);
                let view = w.observe(Side::Human, start + 0.5 * period, s);
                slots += 1;
                if pointed_at(&view, &g) == Some(g.human_id) {
                    hits += 1;
                }
            }
            assert!(
                hits * 10 >= slots * 8,
                "{preset} seed {seed}: {hits} of {slots} gestures resolve to their target"
            );
            targets.sort_unstable();
            targets.dedup();
            assert!(
                targets.len() >= 3,
                "{preset} seed {seed}: always the same targets"
            );
        }
    }
}

#[test]
fn gestures_prefer_objects_both_views_see() {
    let period = Dynamics::default().gesture_period_s;
    let w = world(Preset::Moi, 6);
    for s in 0..30 {
        let start = (T0 / period).floor() * period + s as f64 * period;
        let g = w.gesture(start + 1.0).unwrap();
        let truth = w.truth(start);
        assert!(
            truth.contains(&(g.human_id, g.robot_id)),
            "slot {s}: target not seen by both views at the slot's start"
        );
    }
}

#[test]
fn the_object_count_can_be_fixed() {
    for n in [3, 6, 12] {
        let w = LiveWorld::new(Preset::Moi.config(), Dynamics::default(), 9, Some(n)).unwrap();
        assert_eq!(w.object_count(), n);
    }
}

#[test]
fn bad_dynamics_and_counts_are_refused_by_name() {
    let moi = || Preset::Moi.config();
    let cases: [(Dynamics, &str); 4] = [
        (
            Dynamics {
                absent_share: 1.0,
                ..Dynamics::default()
            },
            "dynamics.absent_share",
        ),
        (
            Dynamics {
                drift_period_s: 0.0,
                ..Dynamics::default()
            },
            "dynamics.drift_period_s",
        ),
        (
            Dynamics {
                cone_half_angle_deg: 120.0,
                ..Dynamics::default()
            },
            "dynamics.cone_half_angle_deg",
        ),
        (
            Dynamics {
                hand_offset: [0.0, f64::NAN, 0.0],
                ..Dynamics::default()
            },
            "dynamics.hand_offset",
        ),
    ];
    for (dynamics, field) in cases {
        let error = LiveWorld::new(moi(), dynamics, 1, None).unwrap_err();
        assert_eq!(field_of(error), field);
    }
    for n in [0, 100_000] {
        let error = LiveWorld::new(moi(), Dynamics::default(), 1, Some(n)).unwrap_err();
        assert_eq!(field_of(error), "objects");
    }
    // Drift room the table cannot give.
    let crowded = Dynamics {
        drift_amplitude: 0.1,
        ..Dynamics::default()
    };
    let error = LiveWorld::new(moi(), crowded, 1, Some(12)).unwrap_err();
    assert_eq!(field_of(error), "objects");
}

#[test]
fn dynamics_have_defaults_and_refuse_unknown_fields() {
    let partial: Dynamics = serde_json::from_str(r#"{"drift_amplitude": 0.02}"#).unwrap();
    assert_eq!(
        partial,
        Dynamics {
            drift_amplitude: 0.02,
            ..Dynamics::default()
        }
    );
    let error = serde_json::from_str::<Dynamics>(r#"{"drift_amplitud": 0.02}"#).unwrap_err();
    assert!(error.to_string().contains("drift_amplitud"), "{error}");
    Dynamics::default().validate().unwrap();
    Dynamics::still().validate().unwrap();
}
