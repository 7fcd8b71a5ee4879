//! `vref segment`: RGB-D frames to 16-bit instance label PNGs with the
//! class-agnostic segmenter, one frame or a folder of scene folders (the
//! OSD layout). Every input problem is refused naming the file.

use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow};
use vref_config::Config;
use vref_logging::exit::{Blame, Failure};
use vref_perception::folder::{
    Camera, DEPTH_FILE, RgbdImages, camera_file_of, colour_file, frame_dirs,
};
use vref_perception::{DepthLaw, LabelImage, RgbdFrame, Segmentation, Segmenter, segment::overlay};

use crate::cli::SegmentArgs;
use crate::stdout;

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
    let mut labels = LabelImage::new(1, 1);
    let jobs: Vec<(String, PathBuf, PathBuf, PathBuf, Option<PathBuf>)> = match &args.dir {
        Some(dir) => {
            let scenes = frame_dirs(dir).bad_input()?;
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
                    (name, colour_file(&path), path.join(DEPTH_FILE), out, over)
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
        (None, Some(dir)) => camera_file_of(dir).bad_input()?,
        (None, None) => return Err(anyhow!("--camera: give the camera file")).bad_input(),
    };
    let (camera, unread) = Camera::read(&camera_path).bad_input()?;
    vref_feed::warn_unread(&unread, &camera_path.display().to_string());
    for (name, rgb, depth, out, over) in jobs {
        let images =
            RgbdImages::load_files(&rgb, &depth, None, camera, config.perception.image_limit())
                .bad_input()?;
        // The thresholds for the camera's noise as the frame shows it
        // (`[segmentation]` is set for a Kinect's).
        // No camera is configured here: unmeasured, [segmentation] as it is.
        let law = vref_feed::frame_law(args.noise, &images.depth, DepthLaw::ZERO, &name);
        let settings = config.segmentation.for_camera(law);
        let mut segmenter = Segmenter::new(settings);
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
