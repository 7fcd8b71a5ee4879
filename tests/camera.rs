//! The camera-only path with real processes: feeds on folders of raw
//! RGB-D frames (`--source rgbd:`), `vref match` on two frames, and
//! `vref import bop --segment`. Each system test has its own root path
//! and prefix, and every wait on another process is bounded.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::time::Duration;

use image::{ImageBuffer, Luma};
use support::{json_lines, vref};
use vref_testkit::{Harness, eventually};
use vref_wire::AnswerStatus;
use vref_wire::ipc::ReferenceClient;

const LIMIT: Duration = Duration::from_secs(120);

/// Both cameras are OSD's Kinect: the headset's depth noise is the
/// robot's, so both views are segmented alike.
const KINECT_BOTH: &str = "\n[perception.human]\npixel = { a = 0.0, b = 0.0, c = 0.0025 }\nsystematic = { a = 0.0, b = 0.005, c = 0.0 }\n";

fn osd_scene(name: &str) -> PathBuf {
    let dir = vref_testkit::data("osd/learn").join(name);
    assert!(
        dir.is_dir(),
        "the OSD data set is missing: {}",
        dir.display()
    );
    dir
}

/// Copies the colour and depth of OSD scene `name` (not its labels) to
/// `to`.
fn copy_frame(name: &str, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for file in ["rgb.png", "depth.png"] {
        std::fs::copy(osd_scene(name).join(file), to.join(file)).unwrap();
    }
}

/// A frame of `dir` that shows a wall: the colour of OSD scene `name`, and
/// one depth for every pixel.
fn wall_frame(name: &str, to: &Path) {
    copy_frame(name, to);
    ImageBuffer::<Luma<u16>, Vec<u16>>::from_pixel(640, 480, Luma([900]))
        .save(to.join("depth.png"))
        .unwrap();
}

fn osd_camera(to: &Path) {
    std::fs::copy(
        vref_testkit::data("osd/camera.json"),
        to.join("camera.json"),
    )
    .unwrap();
}

#[test]
fn feeds_on_rgbd_folders_publish_segmented_objects_that_the_matcher_matches() {
    let mut h = Harness::new("rgbd", KINECT_BOTH);
    let frames = h.dir.path().join("frames");
    osd_camera(
        std::fs::create_dir_all(&frames)
            .map(|()| frames.as_path())
            .unwrap(),
    );
    // A frame of several objects: a view of one or two fixes no motion
    // and is never answered `ok` (docs/method.md).
    copy_frame("learn36", &frames.join("0001"));
    copy_frame("learn7", &frames.join("0002"));
    wall_frame("learn3", &frames.join("0003"));
    // An epoch just passed and an hour's hold: both feeds show frame 0001
    // for the whole test.
    let epoch = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_nanos()
        .to_string();
    let source = format!("rgbd:{}", frames.display());
    h.start("matcher", "vref-matcher", &[]);
    for (name, bin) in [
        ("perception", "vref-perception-feed"),
        ("gesture", "vref-gesture-feed"),
    ] {
        h.start(
            name,
            bin,
            &[
                "--source",
                &source,
                "--rate",
                "30",
                "--hold",
                "1h",
                "--epoch-ns",
                &epoch,
            ],
        );
    }
    let config = vref_config::Config::from_file(&h.config).unwrap();
    let mut client = ReferenceClient::connect(&config.ipc, "test-client").unwrap();
    // Both views are the same frame: label 1 is matched to itself.
    let answer = eventually(Duration::from_secs(30), "an ok answer for label 1", || {
        let a = client.by_human_object(1, Duration::from_millis(500)).ok()?;
        (a.status() == AnswerStatus::Ok).then_some(a)
    });
    assert_eq!(answer.robot_track_id, 1);
    for name in ["perception", "gesture"] {
        assert!(h.running(name), "{name}: {}", h.log(name));
        let log = h.log(name);
        assert!(
            log.contains("3 frames, 0 with their own masks, 1 without a supporting plane"),
            "{name}: {log}"
        );
        assert!(
            log.contains("0003") && log.contains("faces the camera"),
            "{name}: {log}"
        );
    }
}

fn match_frames(robot: &Path, human: &Path, out: &Path) -> support::Run {
    let config = out.with_extension("toml");
    std::fs::write(&config, KINECT_BOTH).unwrap();
    vref(
        &[
            "match",
            robot.to_str().unwrap(),
            human.to_str().unwrap(),
            "--config",
            config.to_str().unwrap(),
            "--json",
            "--labels-out",
            out.to_str().unwrap(),
            "--viz",
            out.join("match.png").to_str().unwrap(),
        ],
        LIMIT,
    )
}

fn labels(path: &Path) -> ImageBuffer<Luma<u16>, Vec<u16>> {
    match image::open(path).unwrap() {
        image::DynamicImage::ImageLuma16(l) => l,
        other => panic!("{}: {:?}, not 16-bit", path.display(), other.color()),
    }
}

#[test]
fn match_pairs_an_osd_scene_with_itself_and_names_its_labels() {
    let dir = tempfile::tempdir().unwrap();
    // A frame folder with the camera inside, and one that finds it two
    // folders up (the OSD layout).
    let robot = dir.path().join("robot");
    copy_frame("learn36", &robot);
    osd_camera(&robot);
    let human = osd_scene("learn36");
    let out = dir.path().join("out");
    let run = match_frames(&robot, &human, &out).ok();
    let lines = json_lines(&run.stdout);
    let human_labels = labels(&out.join("human.png"));
    let robot_labels = labels(&out.join("robot.png"));
    assert_eq!(human_labels.dimensions(), (640, 480));
    let mut present: Vec<u16> = human_labels.pixels().map(|p| p.0[0]).collect();
    present.sort_unstable();
    present.dedup();
    assert!(lines.len() >= 3, "{}", run.stdout);
    assert!(present.len() > lines.len(), "{present:?}");
    let mut ok = 0;
    for line in &lines {
        let label = line["human_label"].as_u64().unwrap() as u16;
        assert!(present.contains(&label), "{line}");
        let [u, v] = [0, 1].map(|k| line["centroid_px"][k].as_f64().unwrap());
        assert!(
            (0.0..640.0).contains(&u) && (0.0..480.0).contains(&v),
            "{line}"
        );
        assert!(line["position"][2].as_f64().unwrap() > 0.3, "{line}");
        let confidence = line["confidence"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&confidence), "{line}");
        let status = line["status"].as_str().unwrap();
        assert!(["ok", "ambiguous", "no_match"].contains(&status), "{line}");
        if status == "ok" {
            ok += 1;
            // The same frame, segmented the same way: each object is its
            // own partner, under the same label.
            assert_eq!(line["robot_label"], line["human_label"], "{line}");
            let robot = line["robot_label"].as_u64().unwrap() as u16;
            assert!(robot_labels.pixels().any(|p| p.0[0] == robot));
        }
    }
    assert!(ok * 10 >= lines.len() * 8, "{}", run.stdout);
    let png = std::fs::read(out.join("match.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");

    // Bad input: exit code 2 and the file named.
    let wall = dir.path().join("small");
    copy_frame("learn36", &wall);
    osd_camera(&wall);
    ImageBuffer::<Luma<u16>, Vec<u16>>::new(320, 240)
        .save(wall.join("depth.png"))
        .unwrap();
    let run = match_frames(&robot, &wall, &out);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(
        run.stderr.contains("small/depth.png is 320x240"),
        "{}",
        run.stderr
    );
    std::fs::write(
        wall.join("camera.json"),
        r#"{"fx": -1, "fy": 525, "cx": 319.5, "cy": 239.5}"#,
    )
    .unwrap();
    let run = match_frames(&robot, &wall, &out);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(
        run.stderr.contains("small/camera.json") && run.stderr.contains("fx is -1"),
        "{}",
        run.stderr
    );
    // A lens vref cannot rectify is refused, not taken for a pinhole.
    std::fs::write(
        wall.join("camera.json"),
        r#"{"fx": 525, "fy": 525, "cx": 319.5, "cy": 239.5, "distortion_model": "fov", "d": [0.1]}"#,
    )
    .unwrap();
    let run = match_frames(&robot, &wall, &out);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(
        run.stderr.contains("small/camera.json") && run.stderr.contains("\"fov\" is not supported"),
        "{}",
        run.stderr
    );
}

/// Real readings seen from elsewhere (`vref_perception::reproject`: an
/// OSD frame's readings from a camera walked 30 degrees around the
/// table): every `ok` answer of `vref match` names a robot segment of
/// the person's segment's physical object (OSD's labels), and most
/// person-side objects are `ok`. learn38's bowl comes out in pieces;
/// learn25's second view merges its two boxes into one segment, which
/// appearance alone once answered `ok` with the wrong box. The same
/// holds when the person's camera is a second sensor: an image 0.75
/// times the size, its own depth noise eight times the frame's, and its
/// own white balance and exposure; and when one object of a cluttered
/// table (learn33) moved 0.2 m before the person looked.
#[test]
fn match_across_viewpoints_of_real_readings_names_the_right_objects() {
    use vref_perception::reproject::{Moved, SecondSensor, Walk, majority, reproject_walked};
    let dir = tempfile::tempdir().unwrap();
    let defaults = dir.path().join("defaults.toml");
    std::fs::write(&defaults, "").unwrap();
    let (mut ok, mut with_object) = (0, 0);
    let second = |c: f64| SecondSensor {
        depth_c: 8.0 * c,
        white_balance: 0.08,
        exposure: 0.15,
        colour_sigma: 2.0,
        seed: 1,
    };
    for (scene, sensor, moving) in [
        ("learn25", false, false),
        ("learn38", false, false),
        ("learn25", true, false),
        ("learn38", true, false),
        ("learn33", false, true),
    ] {
        let pair = dir.path().join(format!("{scene}-{sensor}-{moving}"));
        let robot = pair.join("robot");
        copy_frame(scene, &robot);
        osd_camera(&robot);
        let images = vref_perception::folder::RgbdImages::load(&robot, Default::default()).unwrap();
        let objects = labels(&osd_scene(scene).join("label.png"));
        let view_with = |moved: Option<Moved<'_>>| {
            let walk = Walk {
                yaw_deg: 30.0,
                scale: if sensor { 0.75 } else { 1.0 },
                moved,
            };
            reproject_walked(
                &images.colour,
                &images.depth,
                images.camera.intrinsics,
                &walk,
            )
        };
        // The first of its objects that can move 0.2 m to a free place.
        let mut view = if moving {
            (2..100)
                .find_map(|object| {
                    let readings: Vec<bool> = objects
                        .as_raw()
                        .iter()
                        .map(|&l| vref_testkit::osd_object(l) == object)
                        .collect();
                    let moved = Moved {
                        readings: &readings,
                        metres: 0.2,
                    };
                    readings
                        .contains(&true)
                        .then(|| view_with(Some(moved)).ok())
                        .flatten()
                })
                .unwrap()
        } else {
            view_with(None).unwrap()
        };
        if sensor {
            let c = vref_perception::pixel_noise(&images.depth).unwrap().c;
            second(c).apply(&mut view, images.depth.metres_per_unit());
        }
        let human = pair.join("human");
        std::fs::create_dir_all(&human).unwrap();
        view.colour.save(human.join("rgb.png")).unwrap();
        view.depth.save(human.join("depth.png")).unwrap();
        let camera = vref_perception::folder::Camera {
            intrinsics: view.intrinsics,
            metres_per_unit: images.depth.metres_per_unit(),
            size: Some(view.colour.dimensions()),
            lens: None,
        };
        std::fs::write(human.join("camera.json"), camera.to_json()).unwrap();
        let out = pair.join("labels");
        let run = vref(
            &[
                "match",
                robot.to_str().unwrap(),
                human.to_str().unwrap(),
                "--config",
                defaults.to_str().unwrap(),
                "--json",
                "--labels-out",
                out.to_str().unwrap(),
            ],
            LIMIT,
        )
        .ok();
        let (robot_labels, human_labels) = (
            labels(&out.join("robot.png")),
            labels(&out.join("human.png")),
        );
        for line in json_lines(&run.stdout) {
            let person = line["human_label"].as_u64().unwrap() as u16;
            let object = majority(&human_labels, person, 0.5, |at| {
                view.source[at].map_or(0, |s| {
                    vref_testkit::osd_object(objects.as_raw()[s as usize])
                })
            });
            with_object += usize::from(object.is_some());
            if line["status"] != "ok" {
                continue;
            }
            ok += 1;
            let named = line["robot_label"].as_u64().unwrap() as u16;
            let named = majority(&robot_labels, named, 0.5, |at| {
                vref_testkit::osd_object(objects.as_raw()[at])
            });
            assert!(
                object.is_some() && named == object,
                "{scene} (second sensor {sensor}, moved {moving}): {line} names object {named:?}, not {object:?}"
            );
        }
    }
    assert!(ok * 2 >= with_object, "{ok} ok of {with_object}");
}

/// `vref match` measures each camera's depth noise on its own frame: a
/// real Kinect frame given as both views is segmented alike on both sides
/// under the default configuration, whose headset is eight times as noisy
/// as the Kinect; taken from the configuration (`--noise config`), the
/// person's side is segmented for that headset, and differently.
#[test]
fn match_measures_each_cameras_noise_on_its_own_frame() {
    let dir = tempfile::tempdir().unwrap();
    let frame = dir.path().join("learn20");
    copy_frame("learn20", &frame);
    osd_camera(&frame);
    let defaults = dir.path().join("defaults.toml");
    std::fs::write(&defaults, "").unwrap();
    let labels_with = |noise: &str| {
        let out = dir.path().join(noise);
        let frame = frame.to_str().unwrap();
        let run = support::vref_with(
            &vref_testkit::binary("vref"),
            &[
                "match",
                frame,
                frame,
                "--config",
                defaults.to_str().unwrap(),
                "--noise",
                noise,
                "--labels-out",
                out.to_str().unwrap(),
            ],
            &[("RUST_LOG", "info")],
            LIMIT,
        )
        .ok();
        let robot = labels(&out.join("robot.png"));
        (robot, labels(&out.join("human.png")), run.stderr)
    };
    let (robot, human, log) = labels_with("frame");
    assert!(robot.pixels().any(|p| p.0[0] > 0), "no object: {log}");
    assert!(robot == human, "the same frame segmented otherwise: {log}");
    assert!(log.contains("depth noise measured"), "{log}");
    let (robot, human, _) = labels_with("config");
    assert!(robot != human, "the headset's law changed nothing");
}

#[test]
fn import_bop_segment_gives_vrefs_own_objects_with_ground_truth_by_overlap() {
    let dir = tempfile::tempdir().unwrap();
    let dataset = dir.path().join("table");
    std::fs::create_dir_all(dataset.join("test")).unwrap();
    for scene in ["000001", "000002"] {
        let status = std::process::Command::new("cp")
            .arg("-r")
            .arg(vref_testkit::data("bop/table/test").join(scene))
            .arg(dataset.join("test").join(scene))
            .status()
            .unwrap();
        assert!(status.success());
    }
    let out = dir.path().join("segmented.jsonl");
    let gt = dir.path().join("masks.jsonl");
    let import = |file: &Path, segment: bool| {
        let mut args = vec!["import", "bop", dataset.to_str().unwrap()];
        args.extend(["--out", file.to_str().unwrap()]);
        if segment {
            args.push("--segment");
        }
        vref(&args, LIMIT).ok()
    };
    import(&out, true);
    import(&gt, false);
    let read = |file: &Path| -> Vec<serde_json::Value> {
        std::fs::read_to_string(file)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect()
    };
    let (segmented, masks) = (read(&out), read(&gt));
    assert_eq!(segmented.len(), 2);
    for (s, m) in segmented.iter().zip(&masks) {
        assert_eq!(s["name"], m["name"]);
        let ids = |side: &str| -> Vec<u64> {
            s[side]["objects"]
                .as_array()
                .unwrap()
                .iter()
                .map(|o| o["id"].as_u64().unwrap())
                .collect()
        };
        let (robot, human) = (ids("robot"), ids("human"));
        let truth: Vec<[u64; 2]> = s["ground_truth"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| [p[0].as_u64().unwrap(), p[1].as_u64().unwrap()])
            .collect();
        let dataset_pairs = m["ground_truth"].as_array().unwrap().len();
        // Some of the dataset's pairs survive segmentation, never more;
        // each names one segment of each view, and no segment twice.
        assert!(
            !truth.is_empty() && truth.len() <= dataset_pairs,
            "{}",
            s["name"]
        );
        for [h, r] in &truth {
            assert!(
                human.contains(h) && robot.contains(r),
                "{}: {h} {r}",
                s["name"]
            );
        }
        let mut robots: Vec<u64> = truth.iter().map(|p| p[1]).collect();
        robots.sort_unstable();
        robots.dedup();
        assert_eq!(robots.len(), truth.len(), "{}", s["name"]);
    }
    let run = vref(
        &[
            "eval",
            "--dataset",
            out.to_str().unwrap(),
            "--method",
            "rigid",
            "--json",
        ],
        LIMIT,
    )
    .ok();
    let rigid = &json_lines(&run.stdout)[0];
    assert_eq!(rigid["scenes"], 2, "{rigid}");
}
