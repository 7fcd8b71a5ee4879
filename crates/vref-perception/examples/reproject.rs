//! A second view of one real capture, for `vref match`: the frame's
//! points seen from a virtual camera walked `yaw` degrees around the
//! table (about the supporting plane's normal, through the centre of what
//! stands on it), z-buffered, each reading keeping its own depth and
//! colour. The real sensor's noise, holes and flying pixels stay; what a
//! second sensor adds (its own noise, colours, lens) does not, and what
//! the first camera never saw is a hole. Then, given `vref match`'s
//! answers on the pair, each person-side object against the truth the
//! reprojection knows: the robot segment most of its pixels came from.
//!
//! ```sh
//! cargo run --release -p vref-perception --example reproject -- make FRAME_DIR OUT_DIR YAW_DEG
//! target/release/vref match OUT_DIR/robot OUT_DIR/human --json --labels-out OUT_DIR/labels > OUT_DIR/answers.jsonl
//! cargo run --release -p vref-perception --example reproject -- score OUT_DIR
//! ```
//!
//! `make` writes `OUT_DIR/robot` (the frame as it is), `OUT_DIR/human`
//! (the virtual view), their `camera.json` and `OUT_DIR/yaw`; `score`
//! prints one JSON line of counts (`VERBOSE=1`: each answer and its
//! truth on stderr) (`tools/reprojected-pairs.sh` runs it
//! over a folder of frames).

use std::error::Error;
use std::path::{Path, PathBuf};

use image::{ImageBuffer, Luma, Rgb, RgbImage};
use vref_perception::folder::RgbdImages;
use vref_perception::{
    DepthPixels, ImageLimit, Intrinsics, LabelImage, RgbdFrame, Segmentation, SegmentationSettings,
    Segmenter,
};

type Result<T> = std::result::Result<T, Box<dyn Error>>;

/// A person-side segment's truth needs at least this share of its
/// pixels from one robot segment (or one object).
const MAJORITY: f64 = 0.5;
/// The frame's object labels (OSD's `label.png`: parts of the k-th
/// object are 10k..10k+9, k >= 2; below 20 table or no reading).
const OBJECTS_FILE: &str = "objects.png";

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["make", frame, out, yaw] => make(Path::new(frame), Path::new(out), yaw.parse()?),
        ["score", out] => score(Path::new(out)),
        _ => {
            Err("usage: reproject make FRAME_DIR OUT_DIR YAW_DEG | reproject score OUT_DIR".into())
        }
    }
}

/// The virtual view of a frame: its images, and for every pixel the
/// source pixel it shows (`u32::MAX` for a hole).
struct View {
    colour: RgbImage,
    depth: DepthPixels,
    source: Vec<u32>,
}

fn make(frame: &Path, out: &Path, yaw_deg: f64) -> Result<()> {
    let images = RgbdImages::load(frame, ImageLimit::default())?;
    let view = reproject(&images, yaw_deg)?;
    for (side, colour, depth) in [
        ("robot", &images.colour, images.depth.pixels()),
        ("human", &view.colour, &view.depth),
    ] {
        let dir = out.join(side);
        std::fs::create_dir_all(&dir)?;
        colour.save(dir.join("rgb.png"))?;
        depth.save(dir.join("depth.png"))?;
    }
    let c = images.camera.intrinsics;
    let (w, h) = images.colour.dimensions();
    let camera = serde_json::json!({
        "fx": c.fx(), "fy": c.fy(), "cx": c.cx(), "cy": c.cy(),
        "width": w, "height": h,
        "depth_scale_mm": images.depth.metres_per_unit() * 1000.0,
    });
    std::fs::write(out.join("camera.json"), camera.to_string())?;
    std::fs::write(out.join("yaw"), yaw_deg.to_string())?;
    // OSD's object labels, where the frame has them: which physical
    // object each reading is.
    let objects = frame.join("label.png");
    if objects.is_file() {
        std::fs::copy(objects, out.join(OBJECTS_FILE))?;
    }
    Ok(())
}

/// The frame seen from its camera turned `yaw_deg` about the supporting
/// plane's normal through the centroid of the objects' readings.
fn reproject(images: &RgbdImages, yaw_deg: f64) -> Result<View> {
    let intrinsics = images.camera.intrinsics;
    let mut labels = LabelImage::new(1, 1);
    let frame = RgbdFrame {
        colour: &images.colour,
        depth: &images.depth,
        intrinsics,
        up: None,
    };
    let plane = match Segmenter::new(SegmentationSettings::default())
        .segment(&frame, &mut labels)?
    {
        Segmentation::Objects { plane, .. } => plane,
        Segmentation::NoSupport(why) => return Err(format!("no supporting plane: {why}").into()),
    };
    let (w, h) = images.colour.dimensions();
    let scale = images.depth.metres_per_unit();
    let raw = images.depth.pixels();
    let point = |u: u32, v: u32| -> Option<[f64; 3]> {
        let z = f64::from(raw.get_pixel(u, v).0[0]) * scale;
        (z > 0.0).then(|| unproject(intrinsics, u, v, z))
    };
    let mut sum = [0.0; 3];
    let mut count = 0.0;
    for (u, v, l) in labels.enumerate_pixels() {
        if let (true, Some(p)) = (l.0[0] > 0, point(u, v)) {
            (0..3).for_each(|k| sum[k] += p[k]);
            count += 1.0;
        }
    }
    if count == 0.0 {
        return Err("nothing stands on the plane".into());
    }
    let pivot = sum.map(|s| s / count);
    // The camera turns by `yaw` about the normal through the pivot: the
    // points, seen from it, by the opposite turn.
    let turn = rotation(plane.normal, -yaw_deg.to_radians());
    let mut view = View {
        colour: ImageBuffer::from_pixel(w, h, Rgb([0, 0, 0])),
        depth: DepthPixels::new(w, h),
        source: vec![u32::MAX; (w * h) as usize],
    };
    let mut nearest = vec![f64::INFINITY; (w * h) as usize];
    for v in 0..h {
        for u in 0..w {
            let Some(p) = point(u, v) else { continue };
            let q = moved(&turn, pivot, p);
            if q[2] <= 0.0 {
                continue;
            }
            let x = intrinsics.fx() * q[0] / q[2] + intrinsics.cx();
            let y = intrinsics.fy() * q[1] / q[2] + intrinsics.cy();
            // Each reading covers the 2 x 2 pixels around where it lands,
            // so that a surface seen closer keeps no cracks.
            for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
                let (tx, ty) = ((x + dx - 0.5).floor(), (y + dy - 0.5).floor());
                if tx < 0.0 || ty < 0.0 || tx >= f64::from(w) || ty >= f64::from(h) {
                    continue;
                }
                let at = ty as usize * w as usize + tx as usize;
                if q[2] < nearest[at] {
                    nearest[at] = q[2];
                    view.source[at] = v * w + u;
                    let (tx, ty) = (tx as u32, ty as u32);
                    view.colour
                        .put_pixel(tx, ty, *images.colour.get_pixel(u, v));
                    let units = (q[2] / scale).round().min(f64::from(u16::MAX)) as u16;
                    view.depth.put_pixel(tx, ty, Luma([units]));
                }
            }
        }
    }
    Ok(view)
}

fn unproject(c: Intrinsics, u: u32, v: u32, z: f64) -> [f64; 3] {
    [
        (f64::from(u) - c.cx()) / c.fx() * z,
        (f64::from(v) - c.cy()) / c.fy() * z,
        z,
    ]
}

/// The rotation by `angle` about the unit `axis` (Rodrigues).
fn rotation(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let [x, y, z] = axis;
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]
}

fn moved(r: &[[f64; 3]; 3], pivot: [f64; 3], p: [f64; 3]) -> [f64; 3] {
    let d = [p[0] - pivot[0], p[1] - pivot[1], p[2] - pivot[2]];
    std::array::from_fn(|k| r[k][0] * d[0] + r[k][1] * d[1] + r[k][2] * d[2] + pivot[k])
}

/// One answer line of `vref match --json`.
#[derive(serde::Deserialize)]
struct Answer {
    human_label: u16,
    robot_label: Option<u16>,
    status: String,
}

fn score(out: &Path) -> Result<()> {
    let yaw: f64 = std::fs::read_to_string(out.join("yaw"))?.trim().parse()?;
    let images = RgbdImages::load(&out.join("robot"), ImageLimit::default())?;
    let view = reproject(&images, yaw)?;
    let labels = |name: &str| -> Result<LabelImage> {
        let path: PathBuf = out.join("labels").join(name);
        Ok(image::open(&path)
            .map_err(|e| format!("{}: {e}", path.display()))?
            .into_luma16())
    };
    let (robot, human) = (labels("robot.png")?, labels("human.png")?);
    let objects = out.join(OBJECTS_FILE);
    let objects = objects
        .is_file()
        .then(|| image::open(&objects).map(|i| i.into_luma16()))
        .transpose()?;
    let object_of = |l: u16| if l >= 20 { l / 10 } else { 0 };
    // The value most of `label`'s pixels in `labels` show through `of`
    // (0 and a share under MAJORITY: none).
    let majority = |labels: &LabelImage, label: u16, of: &dyn Fn(usize) -> u16| {
        let mut votes = std::collections::BTreeMap::<u16, usize>::new();
        let mut pixels = 0;
        for (at, l) in labels.as_raw().iter().enumerate() {
            if *l == label {
                pixels += 1;
                *votes.entry(of(at)).or_default() += 1;
            }
        }
        let (&best, &n) = votes
            .iter()
            .max_by_key(|(l, n)| (**n, std::cmp::Reverse(**l)))?;
        (best != 0 && n as f64 >= MAJORITY * f64::from(pixels)).then_some(best)
    };
    let source = |at: usize| view.source.get(at).copied().filter(|&s| s != u32::MAX);
    let truth = |label: u16| {
        majority(&human, label, &|at| {
            source(at).map_or(0, |s| robot.as_raw()[s as usize])
        })
    };
    let human_object = |label: u16| {
        let objects = objects.as_ref()?;
        majority(&human, label, &|at| {
            source(at).map_or(0, |s| object_of(objects.as_raw()[s as usize]))
        })
    };
    let robot_object = |label: u16| {
        let objects = objects.as_ref()?;
        majority(&robot, label, &|at| object_of(objects.as_raw()[at]))
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
        // By object: the person's segment and the named robot segment
        // are mostly the same physical object (a piece of it will do).
        let object = human_object(a.human_label);
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
