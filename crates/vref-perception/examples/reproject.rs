//! A second view of one real capture for `vref match`
//! ([`vref_perception::reproject`]: the frame's readings seen from a
//! virtual camera walked `yaw` degrees around the table), then, given
//! `vref match`'s answers on the pair, each person-side object against
//! the truth the reprojection knows: the robot segment most of its pixels
//! came from, and for `ok` answers the physical object (OSD's labels).
//!
//! ```sh
//! cargo run --release -p vref-perception --example reproject -- make FRAME_DIR OUT_DIR YAW_DEG [--scale S] [--sensor SEED [--noise K]] [--move M]
//! target/release/vref match OUT_DIR/robot OUT_DIR/human --json --labels-out OUT_DIR/labels > OUT_DIR/answers.jsonl
//! cargo run --release -p vref-perception --example reproject -- score OUT_DIR
//! ```
//!
//! `make` writes `OUT_DIR/robot` (the frame as it is), `OUT_DIR/human`
//! (the virtual view), their `camera.json` and `OUT_DIR/view.json`.
//! `--scale S` makes the person's camera's image S (in (0, 1]) times the
//! frame's each way; `--sensor SEED` puts a second sensor on the view
//! (`SecondSensor`: depth noise as large as the frame's own, measured on
//! it, but independent; white balance within 8 % per channel, as the
//! rendered BOP headset's; exposure within 15 %; colour noise of 2
//! levels), so that the two views no longer share one realisation of the
//! noise and the colours; `--noise K` makes its depth noise K times the
//! frame's (8: the rendered BOP headset's against its robot camera).
//! `--move M` moves one object M metres along the table, away from the
//! centre of what stands on it, before the person looks (`Moved`): the
//! object farthest out in the image of those that land where no other
//! object is within 0.1 m (a frame where none can is refused); it needs
//! the frame's OSD labels. `score`
//! prints one JSON line of counts (`VERBOSE=1`: each answer and its
//! truth on stderr) (`tools/reprojected-pairs.sh` runs it
//! over a folder of frames).

use std::error::Error;
use std::path::Path;

use vref_perception::folder::RgbdImages;
use vref_perception::reproject::{
    Moved, ReprojectError, Reprojection, SecondSensor, Walk, majority, reproject_walked,
};
use vref_perception::{ImageLimit, LabelImage, pixel_noise};

type Result<T> = std::result::Result<T, Box<dyn Error>>;

/// A person-side segment's truth needs at least this share of its
/// pixels from one robot segment (or one object).
const MAJORITY: f64 = 0.5;
/// The frame's object labels (OSD's `label.png`: parts of the k-th
/// object are 10k..10k+9, k >= 2; below 20 table or no reading).
const OBJECTS_FILE: &str = "objects.png";
/// How the person's view was made: its yaw, scale and second sensor.
const VIEW_FILE: &str = "view.json";
/// The second sensor's colour response (`--sensor`): fixed before any
/// measurement, from the rendered BOP headset's white balance and a
/// camera's usual auto-exposure spread.
const WHITE_BALANCE: f64 = 0.08;
const EXPOSURE: f64 = 0.15;
const COLOUR_SIGMA: f64 = 2.0;

/// `view.json`.
#[derive(serde::Serialize, serde::Deserialize)]
struct View {
    yaw_deg: f64,
    scale: f64,
    sensor_seed: Option<u64>,
    /// The second sensor's depth noise over the frame's.
    noise: f64,
    /// The OSD object moved before the person looked, and how far.
    moved: Option<(u16, f64)>,
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: reproject make FRAME_DIR OUT_DIR YAW_DEG [--scale S] [--sensor SEED [--noise K]] [--move M] | reproject score OUT_DIR";
    match args.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["make", frame, out, yaw, ref options @ ..] => {
            let mut view = View {
                yaw_deg: yaw.parse()?,
                scale: 1.0,
                sensor_seed: None,
                noise: 1.0,
                moved: None,
            };
            let mut metres = None;
            for pair in options.chunks(2) {
                match pair {
                    ["--scale", s] => view.scale = s.parse()?,
                    ["--sensor", seed] => view.sensor_seed = Some(seed.parse()?),
                    ["--noise", k] => view.noise = k.parse()?,
                    ["--move", m] => metres = Some(m.parse()?),
                    _ => return Err(usage.into()),
                }
            }
            make(Path::new(frame), Path::new(out), view, metres)
        }
        ["score", out] => score(Path::new(out)),
        _ => Err(usage.into()),
    }
}

/// The person's view of `images` as `view` states it (`objects`: the
/// frame's OSD labels, which a moved object needs), through the second
/// sensor where it states one.
fn view_of(images: &RgbdImages, view: &View, objects: Option<&LabelImage>) -> Result<Reprojection> {
    let mut seen = walked(images, view, objects)?;
    if let Some(seed) = view.sensor_seed {
        let noise =
            pixel_noise(&images.depth).ok_or("the frame's depth noise cannot be measured")?;
        let sensor = SecondSensor {
            depth_c: view.noise * noise.c,
            white_balance: WHITE_BALANCE,
            exposure: EXPOSURE,
            colour_sigma: COLOUR_SIGMA,
            seed,
        };
        sensor.apply(&mut seen, images.depth.metres_per_unit());
    }
    Ok(seen)
}

/// [`view_of`] without the second sensor: the camera walked (and the
/// object moved). Its source map, the truth, is the sensor's too.
fn walked(images: &RgbdImages, view: &View, objects: Option<&LabelImage>) -> Result<Reprojection> {
    let readings: Option<Vec<bool>> = match (view.moved, objects) {
        (Some((object, _)), Some(objects)) => Some(
            objects
                .as_raw()
                .iter()
                .map(|&l| vref_testkit::osd_object(l) == object)
                .collect(),
        ),
        (Some(_), None) => return Err("moving an object needs the frame's label.png".into()),
        (None, _) => None,
    };
    let walk = Walk {
        yaw_deg: view.yaw_deg,
        scale: view.scale,
        moved: view
            .moved
            .zip(readings.as_deref())
            .map(|((_, metres), readings)| Moved { readings, metres }),
    };
    Ok(reproject_walked(
        &images.colour,
        &images.depth,
        images.camera.intrinsics,
        &walk,
    )?)
}

/// The OSD objects of `objects`, farthest from the image's centre first.
fn farthest_out(objects: &LabelImage) -> Vec<u16> {
    let (w, h) = objects.dimensions();
    let mut sums = std::collections::BTreeMap::<u16, (f64, f64, f64)>::new();
    for (u, v, l) in objects.enumerate_pixels() {
        let object = vref_testkit::osd_object(l.0[0]);
        if object > 0 {
            let e = sums.entry(object).or_default();
            *e = (e.0 + f64::from(u), e.1 + f64::from(v), e.2 + 1.0);
        }
    }
    let mut out: Vec<(f64, u16)> = sums
        .into_iter()
        .map(|(o, (su, sv, n))| {
            let (du, dv) = (su / n - f64::from(w) / 2.0, sv / n - f64::from(h) / 2.0);
            (du * du + dv * dv, o)
        })
        .collect();
    out.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    out.into_iter().map(|(_, o)| o).collect()
}

/// `how` with the object to move chosen (`metres`: how far, if any), and
/// the view it gives.
fn chosen(
    images: &RgbdImages,
    mut how: View,
    metres: Option<f64>,
    objects: Option<&LabelImage>,
) -> Result<(View, Reprojection)> {
    let Some(metres) = metres else {
        let view = view_of(images, &how, objects)?;
        return Ok((how, view));
    };
    let objects = objects.ok_or("moving an object needs the frame's label.png")?;
    for object in farthest_out(objects) {
        how.moved = Some((object, metres));
        match view_of(images, &how, Some(objects)) {
            Ok(view) => return Ok((how, view)),
            Err(e) if is_not_free(&*e) => continue,
            Err(e) => return Err(e),
        }
    }
    Err(format!("no object can move {metres} m to a free place").into())
}

fn is_not_free(e: &(dyn Error + 'static)) -> bool {
    matches!(
        e.downcast_ref::<ReprojectError>(),
        Some(ReprojectError::NotFree(_))
    )
}

fn make(frame: &Path, out: &Path, how: View, metres: Option<f64>) -> Result<()> {
    let images = RgbdImages::load(frame, ImageLimit::default())?;
    let label_file = frame.join("label.png");
    let objects = label_file
        .is_file()
        .then(|| labels(&label_file))
        .transpose()?;
    let (how, view) = chosen(&images, how, metres, objects.as_ref())?;
    for (side, colour, depth) in [
        ("robot", &images.colour, images.depth.pixels()),
        ("human", &view.colour, &view.depth),
    ] {
        let dir = out.join(side);
        std::fs::create_dir_all(&dir)?;
        colour.save(dir.join("rgb.png"))?;
        depth.save(dir.join("depth.png"))?;
    }
    let camera_json = |intrinsics, size| {
        vref_perception::folder::Camera {
            intrinsics,
            metres_per_unit: images.depth.metres_per_unit(),
            size: Some(size),
            lens: None,
        }
        .to_json()
    };
    std::fs::write(
        out.join("camera.json"),
        camera_json(images.camera.intrinsics, images.colour.dimensions()),
    )?;
    std::fs::write(
        out.join("human").join("camera.json"),
        camera_json(view.intrinsics, view.colour.dimensions()),
    )?;
    std::fs::write(out.join(VIEW_FILE), serde_json::to_string(&how)?)?;
    // OSD's object labels, where the frame has them: which physical
    // object each reading is.
    let objects = frame.join("label.png");
    if objects.is_file() {
        std::fs::copy(objects, out.join(OBJECTS_FILE))?;
    }
    Ok(())
}

/// One answer line of `vref match --json`.
#[derive(serde::Deserialize)]
struct Answer {
    human_label: u16,
    robot_label: Option<u16>,
    status: String,
}

fn score(out: &Path) -> Result<()> {
    let how: View = serde_json::from_str(&std::fs::read_to_string(out.join(VIEW_FILE))?)?;
    let images = RgbdImages::load(&out.join("robot"), ImageLimit::default())?;
    let robot = labels(&out.join("labels/robot.png"))?;
    let human = labels(&out.join("labels/human.png"))?;
    let objects = out.join(OBJECTS_FILE);
    let objects = objects.is_file().then(|| labels(&objects)).transpose()?;
    let view = walked(&images, &how, objects.as_ref())?;
    let source = |at: usize| view.source.get(at).copied().flatten();
    let truth = |label: u16| {
        majority(&human, label, MAJORITY, |at| {
            source(at).map_or(0, |s| robot.as_raw()[s as usize])
        })
    };
    let human_object = |label: u16| {
        let objects = objects.as_ref()?;
        majority(&human, label, MAJORITY, |at| {
            source(at).map_or(0, |s| {
                vref_testkit::osd_object(objects.as_raw()[s as usize])
            })
        })
    };
    let robot_object = |label: u16| {
        let objects = objects.as_ref()?;
        majority(&robot, label, MAJORITY, |at| {
            vref_testkit::osd_object(objects.as_raw()[at])
        })
    };
    let text = std::fs::read_to_string(out.join("answers.jsonl"))?;
    let verbose = std::env::var_os("VERBOSE").is_some();
    let mut counts = serde_json::Map::new();
    let mut add = |key: &str| {
        let n = counts.entry(key).or_insert(0.into());
        *n = (n.as_u64().unwrap_or(0) + 1).into();
    };
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let a: Answer = serde_json::from_str(line)?;
        let t = truth(a.human_label);
        add("objects");
        if t.is_some() {
            add("with_truth");
        }
        let key = match (a.status.as_str(), a.robot_label == t && t.is_some()) {
            ("ok", true) => "ok_right",
            ("ok", false) => "ok_wrong",
            ("ambiguous", true) => "ambiguous_right",
            ("ambiguous", false) => "ambiguous_wrong",
            _ if t.is_some() => "no_partner_with_truth",
            _ => "no_partner_without_truth",
        };
        add(key);
        let object = human_object(a.human_label);
        // The moved object's own answer, counted apart too.
        if how.moved.is_some_and(|(moved, _)| object == Some(moved)) {
            add("moved_seen");
            add(&format!("moved_{key}"));
        }
        // By object: the person's segment and the named robot segment
        // are mostly the same physical object (a piece of it will do).
        if a.status == "ok" && objects.is_some() {
            let same = object.is_some() && a.robot_label.and_then(robot_object) == object;
            add(if same {
                "ok_same_object"
            } else {
                "ok_other_object"
            });
        }
        if verbose {
            eprintln!(
                "person {} -> {:?} {} (truth {t:?}; object {object:?}, named {:?})",
                a.human_label,
                a.robot_label,
                a.status,
                a.robot_label.and_then(robot_object)
            );
        }
    }
    println!("{}", serde_json::Value::Object(counts));
    Ok(())
}

fn labels(path: &Path) -> Result<LabelImage> {
    Ok(image::open(path)
        .map_err(|e| format!("{}: {e}", path.display()))?
        .into_luma16())
}
