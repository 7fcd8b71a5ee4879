//! `vref segment`: RGB-D frames to 16-bit instance label PNGs with the
//! class-agnostic segmenter, one frame or a folder of scene folders (the
//! OSD layout). Every input problem is refused naming the file.

use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow, bail};
use image::RgbImage;
use vref_config::Config;
use vref_perception::{
    DepthImage, ImageLimit, Intrinsics, LabelImage, RgbdFrame, Segmentation, Segmenter,
    load_colour, load_depth, segment::overlay,
};

use crate::cli::SegmentArgs;
use crate::failure::{Blame, Failure};
use crate::stdout;

/// The camera file: a pinhole camera and the depth unit.
#[derive(Debug, serde::Deserialize)]
struct CameraFile {
    fx: f64,
    fy: f64,
    cx: f64,
    cy: f64,
    width: Option<u32>,
    height: Option<u32>,
    /// Millimetres per depth unit.
    #[serde(default = "one")]
    depth_scale_mm: f64,
}

fn one() -> f64 {
    1.0
}

/// A camera's intrinsics, depth unit (metres) and stated image size.
#[derive(Debug, Clone, Copy)]
pub struct Camera {
    pub intrinsics: Intrinsics,
    pub metres_per_unit: f64,
    size: Option<(u32, u32)>,
}

pub fn load_camera(path: &Path) -> anyhow::Result<Camera> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let file: CameraFile = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a camera file", path.display()))?;
    for (name, value) in [("fx", file.fx), ("fy", file.fy)] {
        if !(value.is_finite() && value > 0.0) {
            bail!(
                "{}: {name} is {value}, but must be finite and positive",
                path.display()
            );
        }
    }
    let intrinsics = Intrinsics::new(file.fx, file.fy, file.cx, file.cy)
        .with_context(|| format!("{}: bad intrinsics", path.display()))?;
    let scale = file.depth_scale_mm;
    if !(scale.is_finite() && scale > 0.0) {
        bail!(
            "{}: depth_scale_mm is {scale}, but must be finite and positive",
            path.display()
        );
    }
    let size = match (file.width, file.height) {
        (Some(w), Some(h)) => Some((w, h)),
        (None, None) => None,
        _ => bail!("{}: give both width and height, or neither", path.display()),
    };
    Ok(Camera {
        intrinsics,
        metres_per_unit: scale / 1000.0,
        size,
    })
}

/// The camera file of a folder of scenes: DIR/camera.json, else the one
/// beside DIR (the OSD layout keeps it beside learn/ and test/).
pub fn camera_of(dir: &Path) -> anyhow::Result<PathBuf> {
    let inside = dir.join("camera.json");
    let beside = dir.join("../camera.json");
    [&inside, &beside]
        .into_iter()
        .find(|p| p.is_file())
        .cloned()
        .ok_or_else(|| {
            anyhow!(
                "no camera file: neither {} nor {} exists (give --camera)",
                inside.display(),
                beside.display()
            )
        })
}

/// One frame's decoded images, checked against each other and the camera.
#[derive(Debug)]
pub struct Images {
    pub colour: RgbImage,
    pub depth: DepthImage,
}

pub fn load_frame(
    rgb: &Path,
    depth: &Path,
    camera: &Camera,
    limit: ImageLimit,
) -> anyhow::Result<Images> {
    let colour = load_colour(rgb, limit)?;
    let pixels = load_depth(depth, limit)?;
    let (cw, ch) = colour.dimensions();
    let (dw, dh) = pixels.dimensions();
    if (cw, ch) != (dw, dh) {
        bail!(
            "{} is {dw}x{dh}, but {} is {cw}x{ch}: the depth image must have the colour image's size",
            depth.display(),
            rgb.display()
        );
    }
    if let Some((w, h)) = camera.size
        && (w, h) != (cw, ch)
    {
        bail!(
            "{} is {cw}x{ch}, but the camera file says {w}x{h}",
            rgb.display()
        );
    }
    if pixels.as_raw().iter().all(|&d| d == 0) {
        bail!(
            "{}: every pixel is 0 (no depth reading at all)",
            depth.display()
        );
    }
    let depth = DepthImage::new(pixels, camera.metres_per_unit)?;
    Ok(Images { colour, depth })
}

/// The scene folders of `dir` (those holding rgb.png and depth.png), in
/// natural order (learn2 before learn10).
pub fn scene_dirs(dir: &Path) -> anyhow::Result<Vec<(String, PathBuf)>> {
    let entries = std::fs::read_dir(dir)
        .with_context(|| format!("cannot read the folder {}", dir.display()))?;
    let mut scenes = Vec::new();
    for entry in entries {
        let entry = entry.with_context(|| format!("cannot read the folder {}", dir.display()))?;
        let path = entry.path();
        if path.join("rgb.png").is_file() && path.join("depth.png").is_file() {
            scenes.push((entry.file_name().to_string_lossy().into_owned(), path));
        }
    }
    if scenes.is_empty() {
        bail!(
            "{}: no scene folders (SCENE/rgb.png and SCENE/depth.png)",
            dir.display()
        );
    }
    scenes.sort_by_key(|a| natural_key(&a.0));
    Ok(scenes)
}

/// A name's text before its trailing number, and the number.
pub fn natural_key(name: &str) -> (String, u64, String) {
    let digits = name.len() - name.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    let (stem, number) = name.split_at(name.len() - digits);
    (
        stem.to_owned(),
        number.parse().unwrap_or(u64::MAX),
        name.to_owned(),
    )
}

#[derive(Debug, serde::Serialize)]
struct FrameLine<'a> {
    scene: &'a str,
    objects: usize,
    no_support: Option<String>,
    out: &'a Path,
}

pub fn run(args: &SegmentArgs) -> Result<(), Failure> {
    let (config, source) = Config::load(args.config.as_deref()).bad_input()?;
    tracing::info!(?source, "configuration");
    let mut segmenter = Segmenter::new(config.segmentation);
    let mut labels = LabelImage::new(1, 1);
    let jobs: Vec<(String, PathBuf, PathBuf, PathBuf, Option<PathBuf>)> = match &args.dir {
        Some(dir) => {
            let scenes = scene_dirs(dir).bad_input()?;
            for folder in std::iter::once(&args.out).chain(&args.overlay) {
                std::fs::create_dir_all(folder)
                    .with_context(|| format!("cannot create the folder {}", folder.display()))
                    .runtime()?;
            }
            scenes
                .into_iter()
                .map(|(name, path)| {
                    let out = args.out.join(format!("{name}.png"));
                    let over = args.overlay.as_ref().map(|o| o.join(format!("{name}.png")));
                    (
                        name,
                        path.join("rgb.png"),
                        path.join("depth.png"),
                        out,
                        over,
                    )
                })
                .collect()
        }
        None => {
            let (Some(rgb), Some(depth)) = (&args.rgb, &args.depth) else {
                return Err(anyhow!("give DIR, or --rgb, --depth and --camera")).bad_input();
            };
            let name = rgb
                .parent()
                .and_then(Path::file_name)
                .map_or_else(|| "frame".to_owned(), |n| n.to_string_lossy().into_owned());
            vec![(
                name,
                rgb.clone(),
                depth.clone(),
                args.out.clone(),
                args.overlay.clone(),
            )]
        }
    };
    let camera_path = match (&args.camera, &args.dir) {
        (Some(c), _) => c.clone(),
        (None, Some(dir)) => camera_of(dir).bad_input()?,
        (None, None) => return Err(anyhow!("--camera: give the camera file")).bad_input(),
    };
    let camera = load_camera(&camera_path).bad_input()?;
    for (name, rgb, depth, out, over) in jobs {
        let images =
            load_frame(&rgb, &depth, &camera, config.perception.image_limit()).bad_input()?;
        let frame = RgbdFrame {
            colour: &images.colour,
            depth: &images.depth,
            intrinsics: camera.intrinsics,
            up: None,
        };
        let result = segmenter
            .segment(&frame, &mut labels)
            .with_context(|| format!("{}", rgb.display()))
            .bad_input()?;
        labels
            .save(&out)
            .with_context(|| format!("cannot write {}", out.display()))
            .runtime()?;
        if let Some(over) = &over {
            overlay(&images.colour, &labels)
                .save(over)
                .with_context(|| format!("cannot write {}", over.display()))
                .runtime()?;
        }
        let no_support = match result {
            Segmentation::NoSupport(reason) => Some(reason.to_string()),
            Segmentation::Objects { .. } => None,
        };
        let line = FrameLine {
            scene: &name,
            objects: result.objects(),
            no_support,
            out: &out,
        };
        let text = if args.json {
            serde_json::to_string(&line).context("encoding").runtime()?
        } else {
            match &line.no_support {
                Some(reason) => format!("{name}: 0 objects ({reason}) -> {}", out.display()),
                None => format!("{name}: {} objects -> {}", line.objects, out.display()),
            }
        };
        stdout::print(&format!("{text}\n"))?;
    }
    Ok(())
}
