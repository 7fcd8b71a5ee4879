#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
//! Each source's schedule and content, without shared memory: what
//! `Feed::next` would publish when.

use std::io::Write;
use std::path::{Path, PathBuf};

use vref_config::Config;
use vref_feed::{Due, Feed, FeedArgs, Publication, Role, SetupError, SourceSpec};
use vref_record::{Frame, RecordedObject, RecordedRay, RecordedSnapshot, RecordingWriter};
use vref_scene::Side;
use vref_sim::{Dynamics, LiveWorld, Preset};
use vref_wire::{MAX_FEATURE_DIM, ObjectEntry};

const SECOND: u64 = 1_000_000_000;
/// A wall-clock time in 2024.
const NOW: u64 = 1_720_000_000 * SECOND + 123_456_789;

fn args(source: SourceSpec) -> FeedArgs {
    FeedArgs::with_source(source)
}

fn prepare(role: Role, args: &FeedArgs) -> Result<Feed, SetupError> {
    Feed::prepare(role, args, &Config::default())
}

/// What a due publication is, owned: a snapshot's feature dimension,
/// entries and up vector, or a ray's target.
#[derive(Debug, Clone, PartialEq)]
enum Owned {
    Snapshot(usize, Vec<ObjectEntry>, Option<[f32; 3]>),
    Gesture(u64),
}

/// How long after its due time a publication is out, as `run` would
/// see the clock when it asks for the next.
const LATENCY: u64 = 1_000_000;

/// The next `n` publications, the clock always reading a little after
/// the last one's due time.
fn schedule(feed: &mut Feed, start: u64, n: usize) -> Vec<(u64, Owned)> {
    let mut now = start;
    (0..n)
        .map(|_| {
            let Due { at_ns, publication } = feed.next(now).unwrap();
            assert!(at_ns + LATENCY >= now, "due {at_ns}, long before {now}");
            now = at_ns + LATENCY;
            let owned = match publication {
                Publication::Snapshot {
                    feature_dim,
                    entries,
                    up,
                } => Owned::Snapshot(feature_dim, entries.to_vec(), up),
                Publication::Gesture { target, .. } => {
                    Owned::Gesture(target.map_or(0, |t| t.human_id))
                }
            };
            (at_ns, owned)
        })
        .collect()
}

#[test]
fn sources_are_parsed_and_bad_ones_named() {
    assert_eq!(
        "synthetic".parse::<SourceSpec>().unwrap(),
        SourceSpec::Synthetic
    );
    assert_eq!(
        "dataset:a/b.jsonl".parse::<SourceSpec>().unwrap(),
        SourceSpec::Dataset(PathBuf::from("a/b.jsonl"))
    );
    assert_eq!(
        "recording:/x:y.vrec".parse::<SourceSpec>().unwrap(),
        SourceSpec::Recording(PathBuf::from("/x:y.vrec"))
    );
    for bad in ["camera", "video:x", "synthetic:x", ""] {
        let e = bad.parse::<SourceSpec>().unwrap_err();
        assert!(matches!(e, SetupError::UnknownSource(_)), "{bad}: {e}");
        assert!(e.to_string().contains("dataset:FILE"), "{e}");
    }
    let e = "dataset:".parse::<SourceSpec>().unwrap_err();
    assert!(matches!(e, SetupError::NoFile(_)), "{e}");
}

#[test]
fn synthetic_snapshots_follow_the_rate_and_match_the_world() {
    let mut feed = prepare(Role::Perception, &args(SourceSpec::Synthetic)).unwrap();
    assert_eq!(feed.rate_hz(), Some(30.0));
    assert_eq!(feed.gesture_rate_hz(), None);
    let published = schedule(&mut feed, NOW, 90);
    let world = LiveWorld::new(Preset::Moi.config(), Dynamics::default(), 1, None).unwrap();
    let period = SECOND as f64 / 30.0;
    for (at, what) in &published {
        let Owned::Snapshot(dim, entries, up) = what else {
            panic!("the perception feed pointed");
        };
        // Ticks are aligned to the epoch (0) and numbered from it.
        let tick = (*at as f64 / period).round();
        assert!((*at as f64 - tick * period).abs() < 1000.0);
        let view = world.observe(Side::Robot, tick / 30.0, tick as u64);
        // The world's vertical (+z) in the camera frame, as configured by
        // default ([feeds] up_vectors).
        let vertical = view.camera.direction_to_camera(&nalgebra::Vector3::z());
        let up = up.expect("the synthetic world states which way is up");
        for k in 0..3 {
            assert!(
                (f64::from(up[k]) - vertical[k]).abs() < 1e-6,
                "{up:?} {vertical:?}"
            );
        }
        assert_eq!(*dim, world.config().features.dim());
        assert_eq!(entries.len(), view.objects.len());
        for (e, o) in entries.iter().zip(&view.objects) {
            assert_eq!(e.track_id, o.id);
            let expected: [f32; 3] = o.position.coords.map(|v| v as f32).into();
            assert_eq!(e.position, expected);
            assert_eq!(&e.feature[..*dim], &o.feature[..]);
            assert!(e.feature[*dim..].iter().all(|&v| v == 0.0));
        }
    }
    let gaps: Vec<u64> = published.windows(2).map(|w| w[1].0 - w[0].0).collect();
    assert!(
        gaps.iter().all(|&g| g.abs_diff(SECOND / 30) < 1000),
        "{gaps:?}"
    );
    // A feed that fell behind skips to the latest tick due instead of
    // publishing every missed one in a burst.
    let last = published.last().unwrap().0;
    let late = last + SECOND;
    let Due { at_ns, .. } = feed.next(late).unwrap();
    assert!(
        at_ns <= late && at_ns + SECOND / 30 >= late,
        "{at_ns} vs {late}"
    );
}

#[test]
fn the_gesture_feed_interleaves_rays_without_losing_ticks() {
    let mut feed = prepare(Role::Gesture, &args(SourceSpec::Synthetic)).unwrap();
    assert_eq!(feed.gesture_rate_hz(), Some(2.0));
    // Ten seconds: 300 snapshots and 20 rays, every ray tick on a
    // snapshot tick.
    let published = schedule(&mut feed, 1_720_000_000 * SECOND, 320);
    let snapshots = published
        .iter()
        .filter(|(_, w)| matches!(w, Owned::Snapshot(..)))
        .count();
    let rays: Vec<&(u64, Owned)> = published
        .iter()
        .filter(|(_, w)| matches!(w, Owned::Gesture(_)))
        .collect();
    assert_eq!((snapshots, rays.len()), (300, 20));
    for pair in rays.windows(2) {
        assert_eq!(pair[1].0 - pair[0].0, SECOND / 2);
    }
    // Two processes agree: a second feed started later publishes the same
    // thing for the same tick.
    let mut other = prepare(Role::Gesture, &args(SourceSpec::Synthetic)).unwrap();
    let later = schedule(&mut other, 1_720_000_000 * SECOND + SECOND, 40);
    let mut compared = 0;
    for (at, what) in &later {
        let same_kind = |w: &Owned| std::mem::discriminant(w) == std::mem::discriminant(what);
        if let Some((_, mine)) = published.iter().find(|(a, w)| a == at && same_kind(w)) {
            assert_eq!(mine, what);
            compared += 1;
        }
    }
    assert_eq!(compared, 40);
}

#[test]
fn a_synthetic_world_can_be_sized_and_refuses_impossible_sizes() {
    let mut sized = args(SourceSpec::Synthetic);
    sized.objects = Some(5);
    let feed = prepare(Role::Perception, &sized).unwrap();
    assert!(feed.describe().contains("5 objects"), "{}", feed.describe());
    sized.objects = Some(0);
    let e = prepare(Role::Perception, &sized).unwrap_err();
    assert!(matches!(e, SetupError::World(_)), "{e}");
}

#[test]
fn bad_rates_and_presets_are_refused() {
    let mut bad = args(SourceSpec::Synthetic);
    bad.rate = Some(0.0);
    let e = prepare(Role::Perception, &bad).unwrap_err();
    assert!(e.to_string().contains("--rate"), "{e}");

    let mut config = Config::default();
    config.feeds.gesture_rate_hz = f64::NAN;
    let e = Feed::prepare(Role::Gesture, &args(SourceSpec::Synthetic), &config).unwrap_err();
    assert!(e.to_string().contains("gesture_rate_hz"), "{e}");
    // The perception feed does not point: the gesture rate is not its.
    Feed::prepare(Role::Perception, &args(SourceSpec::Synthetic), &config).unwrap();

    let mut config = Config::default();
    config.feeds.preset = "kitchen".to_owned();
    let e = Feed::prepare(Role::Perception, &args(SourceSpec::Synthetic), &config).unwrap_err();
    assert!(matches!(e, SetupError::Preset(_)), "{e}");
}

fn scene_line(name: &str, robot_ids: &[u64], human_ids: &[u64], dim: usize) -> String {
    let objects = |ids: &[u64]| {
        ids.iter()
            .enumerate()
            .map(|(k, id)| {
                let feature = vec![0.5; dim];
                format!(
                    r#"{{"id":{id},"position":[{k},0.1,1.0],"feature":{}}}"#,
                    serde_json_array(&feature)
                )
            })
            .collect::<Vec<_>>()
            .join(",")
    };
    format!(
        r#"{{"name":"{name}","robot":{{"objects":[{}]}},"human":{{"objects":[{}]}},"ground_truth":[]}}"#,
        objects(robot_ids),
        objects(human_ids)
    )
}

/// `line` (of [`scene_line`]) with `side`'s view given an up vector.
fn with_up(line: &str, side: &str, up: [f64; 3]) -> String {
    let [x, y, z] = up;
    let view = format!(r#""{side}":{{"#);
    assert!(line.contains(&view), "{line}");
    line.replacen(&view, &format!(r#"{view}"up":[{x},{y},{z}],"#), 1)
}

fn serde_json_array(values: &[f32]) -> String {
    let items: Vec<String> = values.iter().map(|v| v.to_string()).collect();
    format!("[{}]", items.join(","))
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_dataset_shows_each_pair_for_the_hold_time_in_turn() {
    let dir = tempfile::tempdir().unwrap();
    let text = [
        scene_line("a", &[1, 2, 3], &[11, 12, 13], 4),
        with_up(
            &scene_line("b", &[4, 5], &[14, 15, 16, 17], 4),
            "robot",
            [0.0, -2.0, 0.0],
        ),
        with_up(
            &scene_line("c", &[6, 7, 8, 9], &[18, 19], 4),
            "human",
            [3.0, 0.0, -4.0],
        ),
    ]
    .join("\n");
    let path = write(dir.path(), "three.jsonl", &text);
    for (role, first_ids) in [
        (Role::Perception, [1u64, 4, 6]),
        (Role::Gesture, [11, 14, 18]),
    ] {
        let mut a = args(SourceSpec::Dataset(path.clone()));
        a.hold = std::time::Duration::from_secs(1);
        a.rate = Some(10.0);
        let mut feed = prepare(role, &a).unwrap();
        assert!(feed.describe().contains("3 scene pairs"));
        // Start at a pair boundary: 10 snapshots per pair.
        let start = 3 * 1_000_000 * SECOND;
        let published = schedule(&mut feed, start, 60);
        for (k, (at, what)) in published.iter().enumerate() {
            let Owned::Snapshot(dim, entries, up) = what else {
                panic!("a dataset has no rays");
            };
            assert_eq!(*dim, 4);
            let pair = ((at - start) / SECOND) as usize % 3;
            assert_eq!(entries[0].track_id, first_ids[pair], "snapshot {k}");
            // Pair b's robot view and pair c's human view know which way
            // is up; it is published at unit length.
            let expected = match (role, pair) {
                (Role::Perception, 1) => Some([0.0, -1.0, 0.0]),
                (Role::Gesture, 2) => Some([0.6, 0.0, -0.8]),
                _ => None,
            };
            assert_eq!(*up, expected, "snapshot {k}");
        }
    }
}

#[test]
fn dataset_problems_are_refused_before_anything_is_published() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.jsonl");
    let e = prepare(Role::Perception, &args(SourceSpec::Dataset(missing))).unwrap_err();
    assert!(e.to_string().contains("missing.jsonl"), "{e}");

    let empty = write(dir.path(), "empty.jsonl", "");
    let e = prepare(Role::Perception, &args(SourceSpec::Dataset(empty))).unwrap_err();
    assert!(matches!(e, SetupError::EmptyDataset { .. }), "{e}");

    // Features longer than the wire carries are an error, not cut short.
    let wide = write(
        dir.path(),
        "wide.jsonl",
        &scene_line("wide", &[1, 2], &[3, 4], MAX_FEATURE_DIM + 1),
    );
    let e = prepare(Role::Gesture, &args(SourceSpec::Dataset(wide))).unwrap_err();
    let text = format!("{:?}", anyhow_chain(&e));
    assert!(text.contains("65") && text.contains("64"), "{text}");

    let mut a = args(SourceSpec::Dataset(write(
        dir.path(),
        "ok.jsonl",
        &scene_line("ok", &[1], &[2], 2),
    )));
    a.hold_s = Some(-1.0);
    let e = prepare(Role::Perception, &a).unwrap_err();
    assert!(e.to_string().contains("--hold-s"), "{e}");
}

fn anyhow_chain(e: &dyn std::error::Error) -> Vec<String> {
    let mut chain = vec![e.to_string()];
    let mut source = e.source();
    while let Some(s) = source {
        chain.push(s.to_string());
        source = s.source();
    }
    chain
}

fn recorded(robot: bool, timestamp_ns: u64, id: u64, dim: usize) -> Frame {
    Frame::Snapshot(RecordedSnapshot {
        robot,
        sequence: timestamp_ns,
        timestamp_ns,
        frame_name: "x".to_owned(),
        feature_dim: dim as u32,
        objects: vec![RecordedObject {
            track_id: id,
            position: [0.1, 0.2, 0.9],
            position_sigma: [0.01, 0.01, 0.05],
            feature: vec![0.25; dim],
        }],
        up: None,
    })
}

fn recording(dir: &Path, name: &str, frames: &[Frame]) -> PathBuf {
    let path = dir.join(name);
    let mut writer = RecordingWriter::new(std::fs::File::create(&path).unwrap()).unwrap();
    for f in frames {
        writer.write(f).unwrap();
    }
    writer.finish().unwrap().flush().unwrap();
    path
}

#[test]
fn a_recording_replays_its_side_with_the_original_spacing_looping() {
    let dir = tempfile::tempdir().unwrap();
    let t = NOW;
    let ray = Frame::Gesture(RecordedRay {
        sequence: 1,
        timestamp_ns: t + 150_000_000,
        origin: [0.0; 3],
        direction: [0.0, 0.0, 1.0],
        cone_half_angle: 0.2,
        confidence: 0.9,
    });
    // Arrival order is not timestamp order across feeds.
    let frames = [
        recorded(true, t, 1, 3),
        recorded(false, t + 10_000_000, 2, 3),
        recorded(true, t + 100_000_000, 3, 3),
        ray,
        recorded(false, t + 90_000_000, 4, 3),
        recorded(true, t + 200_000_000, 5, 3),
    ];
    let path = recording(dir.path(), "r.vrec", &frames);

    let mut robot = prepare(Role::Perception, &args(SourceSpec::Recording(path.clone()))).unwrap();
    assert_eq!(robot.rate_hz(), None);
    let start = 5 * SECOND;
    let published = schedule(&mut robot, start, 7);
    let ids: Vec<u64> = published
        .iter()
        .map(|(_, w)| match w {
            Owned::Snapshot(3, e, _) => {
                assert_eq!(e[0].position_sigma, [0.01, 0.01, 0.05]);
                e[0].track_id
            }
            other => panic!("unexpected {other:?}"),
        })
        .collect();
    assert_eq!(ids, [1, 3, 5, 1, 3, 5, 1]);
    let offsets: Vec<u64> = published.iter().map(|(at, _)| at - start).collect();
    // One pass: the last offset plus the mean gap (100 ms).
    let ms = 1_000_000;
    assert_eq!(
        offsets,
        [
            0,
            100 * ms,
            200 * ms,
            300 * ms,
            400 * ms,
            500 * ms,
            600 * ms
        ]
    );

    let mut human = prepare(Role::Gesture, &args(SourceSpec::Recording(path))).unwrap();
    let published = schedule(&mut human, start, 3);
    let kinds: Vec<Owned> = published.into_iter().map(|(_, w)| w).collect();
    assert!(matches!(&kinds[0], Owned::Snapshot(_, e, _) if e[0].track_id == 2));
    assert!(matches!(&kinds[1], Owned::Snapshot(_, e, _) if e[0].track_id == 4));
    assert_eq!(kinds[2], Owned::Gesture(0));
}

#[test]
fn a_recording_replays_each_snapshots_up_vector_as_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let with = |frame: Frame, up: Option<[f32; 3]>| match frame {
        Frame::Snapshot(s) => Frame::Snapshot(RecordedSnapshot { up, ..s }),
        other => other,
    };
    // A zero vector is replayed too: a replay reproduces what was sent,
    // and the matcher refuses it again.
    let ups = [Some([0.0, -1.0, 0.0]), None, Some([0.0; 3])];
    let frames: Vec<Frame> = ups
        .iter()
        .enumerate()
        .map(|(k, up)| with(recorded(true, NOW + k as u64 * SECOND, 1, 2), *up))
        .collect();
    let path = recording(dir.path(), "up.vrec", &frames);
    let mut feed = prepare(Role::Perception, &args(SourceSpec::Recording(path))).unwrap();
    let published: Vec<Option<[f32; 3]>> = schedule(&mut feed, NOW, 3)
        .into_iter()
        .map(|(_, w)| match w {
            Owned::Snapshot(_, _, up) => up,
            other => panic!("unexpected {other:?}"),
        })
        .collect();
    assert_eq!(published, ups);
}

#[test]
fn recording_problems_are_refused_before_anything_is_published() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("none.vrec");
    let e = prepare(Role::Perception, &args(SourceSpec::Recording(missing))).unwrap_err();
    assert!(matches!(e, SetupError::OpenRecording { .. }), "{e}");

    let junk = write(dir.path(), "junk.vrec", "not a recording");
    let e = prepare(Role::Perception, &args(SourceSpec::Recording(junk))).unwrap_err();
    assert!(matches!(e, SetupError::Recording { .. }), "{e}");

    let human_only = recording(dir.path(), "h.vrec", &[recorded(false, NOW, 1, 3)]);
    let e = prepare(Role::Perception, &args(SourceSpec::Recording(human_only))).unwrap_err();
    assert!(e.to_string().contains("robot snapshots"), "{e}");

    let wide = recording(
        dir.path(),
        "w.vrec",
        &[recorded(true, NOW, 1, MAX_FEATURE_DIM + 1)],
    );
    let e = prepare(Role::Perception, &args(SourceSpec::Recording(wide))).unwrap_err();
    assert!(matches!(e, SetupError::Entry { .. }), "{e}");
}

/// One real Kinect frame (OSD learn20) as a folder of one frame, with
/// its camera.
fn osd_frame(dir: &Path) -> PathBuf {
    let scene = vref_testkit::data("osd/learn/learn20");
    assert!(
        scene.is_dir(),
        "the OSD data set is missing: {}",
        scene.display()
    );
    let frame = dir.join("learn20");
    std::fs::create_dir_all(&frame).unwrap();
    for file in ["rgb.png", "depth.png"] {
        std::fs::copy(scene.join(file), frame.join(file)).unwrap();
    }
    std::fs::copy(
        vref_testkit::data("osd/camera.json"),
        dir.join("camera.json"),
    )
    .unwrap();
    dir.to_owned()
}

/// The objects the first snapshot of `role`'s feed on `dir` holds.
fn first_objects(
    role: Role,
    dir: &Path,
    noise: Option<vref_perception::NoiseSource>,
) -> Vec<ObjectEntry> {
    let mut args = args(SourceSpec::Rgbd(dir.to_owned()));
    args.noise = noise;
    let mut feed = prepare(role, &args).unwrap();
    match feed.next(NOW).unwrap().publication {
        Publication::Snapshot { entries, .. } => entries.to_vec(),
        Publication::Gesture { .. } => panic!("an rgbd: feed points"),
    }
}

/// Each feed measures the depth noise its frames show (`--noise frame`,
/// the default): one Kinect frame given to both feeds is segmented alike,
/// although the headset is configured eight times noisier. With the
/// configured laws (`--noise config`) the two differ.
#[test]
fn an_rgbd_feed_segments_for_the_noise_its_frames_show() {
    use vref_perception::NoiseSource;
    let dir = tempfile::tempdir().unwrap();
    let frames = osd_frame(dir.path());
    let ids = |entries: &[ObjectEntry]| entries.iter().map(|e| e.track_id).collect::<Vec<_>>();
    let robot = first_objects(Role::Perception, &frames, None);
    let human = first_objects(Role::Gesture, &frames, None);
    assert!(!robot.is_empty());
    assert_eq!(ids(&robot), ids(&human));
    for (r, h) in robot.iter().zip(&human) {
        assert_eq!(r.position, h.position, "object {}", r.track_id);
    }
    let configured = first_objects(Role::Gesture, &frames, Some(NoiseSource::Config));
    assert_ne!(
        ids(&configured),
        ids(&robot),
        "the headset's law changed nothing"
    );
    assert_eq!(
        ids(&first_objects(
            Role::Perception,
            &frames,
            Some(NoiseSource::Frame)
        )),
        ids(&robot)
    );
}
