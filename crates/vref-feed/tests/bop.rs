#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! The BOP source on the shared table scenes: what the two feeds publish
//! when, without shared memory, and the pointing targets they agree on.

use std::collections::HashSet;
use std::path::PathBuf;

use vref_config::Config;
use vref_feed::{BopWorld, Due, Feed, FeedArgs, Publication, Role, SourceSpec};
use vref_perception::PerceptionSettings;
use vref_scene::Limits;

const SECOND: u64 = 1_000_000_000;
const NOW: u64 = 1_720_000_000 * SECOND;

fn table() -> PathBuf {
    vref_testkit::data("bop/table")
}

fn world() -> BopWorld {
    BopWorld::load(
        &table(),
        None,
        PerceptionSettings::default(),
        Limits::default(),
        5.0,
    )
    .unwrap()
}

#[test]
fn targets_are_true_pairs_of_the_scene_shown_and_change_per_slot() {
    let world = world();
    assert_eq!(world.pairs().len(), 12);
    let mut ids = HashSet::new();
    for pair in world.pairs() {
        for o in pair.robot.objects().iter().chain(pair.human.objects()) {
            assert!(ids.insert(o.id), "id {} names two objects", o.id);
        }
    }
    let (mut slots, mut chosen) = (HashSet::new(), HashSet::new());
    for k in 0..120 {
        let t = 1_720_000_000.0 + 0.5 * f64::from(k);
        let g = world.gesture(t).unwrap();
        assert_eq!(g.scene, world.scene_at(t), "t {t}");
        let pair = &world.pairs()[g.scene];
        assert!(pair.ground_truth.contains(&(g.human_id, g.robot_id)));
        let norm = g.direction.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!((norm - 1.0).abs() < 1e-9);
        assert!(t - g.since_s >= 0.0 && t - g.since_s < world.slot_s());
        slots.insert(g.slot);
        chosen.insert(g.human_id);
    }
    // 60 s: 24 slots of 2.5 s (25 when the start falls inside one), each
    // a target of its own scene.
    assert!((24..=25).contains(&slots.len()), "{}", slots.len());
    assert!(chosen.len() >= 20, "{} targets", chosen.len());
}

#[test]
fn both_feeds_show_the_scene_of_the_moment_and_the_gesture_feed_points() {
    let args = FeedArgs::with_source(SourceSpec::Bop(table()));
    let world = world();
    let config = Config::default();
    for role in [Role::Perception, Role::Gesture] {
        let mut feed = Feed::prepare(role, &args, &config).unwrap();
        let (mut snapshots, mut rays) = (0, 0);
        let mut now = NOW;
        while now < NOW + 3 * SECOND {
            let Due { at_ns, publication } = feed.next(now).unwrap();
            let t = at_ns as f64 / 1e9;
            let pair = &world.pairs()[world.scene_at(t)];
            match publication {
                Publication::Snapshot { entries, .. } => {
                    let graph = match role {
                        Role::Perception => &pair.robot,
                        Role::Gesture => &pair.human,
                    };
                    let ids: Vec<u64> = entries.iter().map(|e| e.track_id).collect();
                    let want: Vec<u64> = graph.objects().iter().map(|o| o.id).collect();
                    assert_eq!(ids, want);
                    assert!(entries.iter().all(|e| e.position_sigma[2] > 0.0));
                    snapshots += 1;
                }
                Publication::Gesture { target, .. } => {
                    let target = target.unwrap();
                    assert_eq!(target.human_id, world.gesture(t).unwrap().human_id);
                    rays += 1;
                }
            }
            now = at_ns + 1_000_000;
        }
        assert!(snapshots >= 80, "{role:?}: {snapshots} snapshots in 3 s");
        match role {
            Role::Perception => assert_eq!(rays, 0),
            Role::Gesture => assert!(rays >= 5, "{rays} rays in 3 s"),
        }
    }
    assert_eq!(
        "bop:a/b".parse::<SourceSpec>().unwrap(),
        SourceSpec::Bop(PathBuf::from("a/b"))
    );
    let missing = FeedArgs {
        source: SourceSpec::Bop(PathBuf::from("/nonexistent/bop")),
        ..args
    };
    let err = Feed::prepare(Role::Perception, &missing, &config).unwrap_err();
    assert!(err.to_string().contains("/nonexistent/bop"), "{err}");
}

#[test]
fn each_scene_names_its_images_and_the_track_id_of_every_measured_mask() {
    let world = world();
    assert_eq!(world.sources().len(), world.pairs().len());
    for (pair, source) in world.pairs().iter().zip(world.sources()) {
        assert_eq!(source.name, pair.name);
        assert!(source.scene.colour_path(source.robot.image).is_file());
        assert!(source.scene.colour_path(source.human.image).is_file());
        for (graph, image) in [(&pair.robot, &source.robot), (&pair.human, &source.human)] {
            let mut published: Vec<u64> = graph.objects().iter().map(|o| o.id).collect();
            let mut named: Vec<u64> = image.track_ids.iter().flatten().copied().collect();
            published.sort_unstable();
            named.sort_unstable();
            assert_eq!(named, published, "{}", pair.name);
            let k = image.track_ids.len().saturating_sub(1);
            assert!(source.scene.mask_path(image.image, k).is_file());
        }
    }
}

/// With the world's up (the rendered scenes stand on z) every view carries
/// its camera's up vector, and the two cameras agree on it: true edges
/// rise as far along the robot's up as along the headset's. Without
/// it no view has one, and the feeds publish what the world holds.
#[test]
fn the_worlds_up_gives_each_view_its_cameras_up_vector() {
    let upright = BopWorld::load(
        &table(),
        Some([0.0, 0.0, 1.0]),
        PerceptionSettings::default(),
        Limits::default(),
        5.0,
    )
    .unwrap();
    let mut gaps = Vec::new();
    for pair in upright.pairs() {
        let (hu, ru) = (pair.human.up().unwrap(), pair.robot.up().unwrap());
        let place = |graph: &vref_scene::SceneGraph, id: u64| {
            graph.objects()[graph.index_of(id).unwrap()].position
        };
        for (graph, up) in [(&pair.human, hu), (&pair.robot, ru)] {
            // Up, and not some other fixed direction: the objects lie on
            // the table below the camera, and spread across up far more
            // than along it.
            let heights: Vec<f64> = graph
                .objects()
                .iter()
                .map(|o| up.dot(&o.position.coords))
                .collect();
            let below = heights.iter().all(|&h| h < -0.1);
            let rise = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max)
                - heights.iter().copied().fold(f64::INFINITY, f64::min);
            let across = graph
                .objects()
                .iter()
                .flat_map(|a| {
                    graph.objects().iter().map(move |b| {
                        let d = a.position - b.position;
                        (d - up * up.dot(&d)).norm()
                    })
                })
                .fold(0.0, f64::max);
            assert!(
                below && rise < 0.25 * across,
                "{}: rise {rise}, across {across}",
                pair.name
            );
        }
        let truth = &pair.ground_truth;
        for (a, &(h1, r1)) in truth.iter().enumerate() {
            for &(h2, r2) in &truth[a + 1..] {
                let human_rise = hu.dot(&(place(&pair.human, h1) - place(&pair.human, h2)));
                let robot_rise = ru.dot(&(place(&pair.robot, r1) - place(&pair.robot, r2)));
                gaps.push((human_rise - robot_rise).abs());
            }
        }
    }
    // The views measure each object's visible surface, not one point: a
    // few centimetres apart at most (8 mm median, 3.7 cm largest here).
    gaps.sort_by(f64::total_cmp);
    assert!(gaps.len() > 100, "{} edges", gaps.len());
    assert!(
        gaps[gaps.len() / 2] < 0.015,
        "median {}",
        gaps[gaps.len() / 2]
    );
    assert!(
        gaps[gaps.len() - 1] < 0.05,
        "largest {}",
        gaps[gaps.len() - 1]
    );
    assert!(
        world()
            .pairs()
            .iter()
            .all(|p| p.human.up().is_none() && p.robot.up().is_none())
    );

    let args = |source, world_up| FeedArgs {
        world_up,
        ..FeedArgs::with_source(source)
    };
    let config = Config::default();
    let mut feed = Feed::prepare(
        Role::Perception,
        &args(SourceSpec::Bop(table()), Some([0.0, 0.0, 1.0])),
        &config,
    )
    .unwrap();
    let Due { at_ns, publication } = feed.next(NOW).unwrap();
    let Publication::Snapshot { up: Some(up), .. } = publication else {
        panic!("no up vector published: {publication:?}");
    };
    let want = upright.pairs()[upright.scene_at(at_ns as f64 / 1e9)]
        .robot
        .up()
        .unwrap();
    assert!(
        (0..3).all(|k| (f64::from(up[k]) - want[k]).abs() < 1e-6),
        "{up:?} against {want}"
    );

    let err = Feed::prepare(
        Role::Perception,
        &args(SourceSpec::Synthetic, Some([0.0, 0.0, 1.0])),
        &config,
    )
    .err()
    .unwrap();
    assert!(
        err.to_string().contains("--world-up") && err.to_string().contains("synthetic"),
        "{err}"
    );
}

/// A scene whose cameras have no pose keeps being fed with --world-up,
/// without up vectors (and a warning), rather than with made-up ones.
#[test]
fn a_camera_without_a_pose_gives_no_up_vector() {
    let dir = tempfile::tempdir().unwrap();
    let dataset = dir.path().join("table");
    std::fs::create_dir_all(dataset.join("test")).unwrap();
    std::fs::copy(table().join("camera.json"), dataset.join("camera.json")).unwrap();
    let status = std::process::Command::new("cp")
        .arg("-r")
        .arg(table().join("test/000000"))
        .arg(dataset.join("test/000000"))
        .status()
        .unwrap();
    assert!(status.success());
    let cameras = dataset.join("test/000000/scene_camera.json");
    let text = std::fs::read_to_string(&cameras).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    for camera in json.as_object_mut().unwrap().values_mut() {
        let camera = camera.as_object_mut().unwrap();
        assert!(camera.remove("cam_R_w2c").is_some());
        camera.remove("cam_t_w2c");
    }
    std::fs::write(&cameras, json.to_string()).unwrap();
    let world = BopWorld::load(
        &dataset,
        Some([0.0, 0.0, 1.0]),
        PerceptionSettings::default(),
        Limits::default(),
        5.0,
    )
    .unwrap();
    assert_eq!(world.pairs().len(), 1);
    let pair = &world.pairs()[0];
    assert!(pair.robot.up().is_none() && pair.human.up().is_none());
    assert!(!pair.robot.objects().is_empty());
}
