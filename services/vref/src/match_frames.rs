//! `vref match ROBOT_DIR HUMAN_DIR`: the one-shot camera-only path. Two
//! RGB-D frame folders in (masks optional: the segmenter makes them),
//! objects measured by the front end, matched by the configured method,
//! each person-side object's answer out with the status the live matcher
//! would give it, the labels the answers name, and a picture.

use std::path::Path;

use anyhow::Context;
use vref_config::Config;
use vref_logging::exit::{Blame, Failure};
use vref_match::{Method, OkRule, Params, Problem, Solution, SolveOptions, Verdict, solve_with};
use vref_perception::folder::RgbdImages;
use vref_perception::{
    Detection, Frame, FrontEnd, LabelImage, LabelMask, Mask, RgbdFrame, Segmentation, Segmenter,
    label_masks,
};
use vref_scene::{Limits, SceneGraph, SceneObject};
use vref_viz::{Answer, AnswerPicture, AnswerStatus, ImageObject, ViewImage};

use crate::cli::MatchArgs;
use crate::stdout;

/// One camera's frame, its labels and what the front end measured.
struct View {
    images: RgbdImages,
    labels: LabelImage,
    masks: Vec<LabelMask>,
    /// Ids are the labels.
    detections: Vec<Detection>,
    /// The supporting plane's normal, where the segmenter found one.
    up: Option<[f64; 3]>,
}

/// One line of `--json`.
#[derive(Debug, serde::Serialize)]
struct AnswerLine {
    human_label: u16,
    robot_label: Option<u16>,
    status: &'static str,
    confidence: f64,
    centroid_px: [f64; 2],
    position: [f64; 3],
}

pub fn run(args: &MatchArgs) -> Result<(), Failure> {
    let (config, source) = Config::load(args.config.as_deref()).bad_input()?;
    tracing::info!(?source, "configuration");
    let method = match args.method {
        Some(m) => m,
        None => config
            .matcher
            .method()
            .context("[matcher] method")
            .bad_input()?,
    };
    let perception = config.perception;
    let limit = perception.image_limit();
    let cameras = [
        (&args.robot, "robot", perception.robot()),
        (&args.human, "person", perception.human()),
    ];
    let [robot, human] = cameras.map(|(dir, who, mut settings)| {
        let images = RgbdImages::load(dir, limit)
            .with_context(|| format!("the {who}'s frame {}", dir.display()))
            .bad_input()?;
        vref_feed::warn_unread(&images.unread_keys, who);
        // Each camera's segmenter is set for its own depth noise.
        settings.noise.pixel =
            vref_feed::frame_law(args.noise, &images.depth, settings.noise.pixel, who);
        let mut segmenter = Segmenter::new(config.segmentation.for_camera(settings.noise.pixel));
        view(images, dir, &mut segmenter, &mut FrontEnd::new(settings))
    });
    let (robot, human) = (robot?, human?);
    let lines = answer(&human, &robot, method, &config)?;
    if let Some(dir) = &args.labels_out {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the folder {}", dir.display()))
            .runtime()?;
        for (name, v) in [("robot.png", &robot), ("human.png", &human)] {
            let path = dir.join(name);
            v.labels
                .save(&path)
                .with_context(|| format!("cannot write {}", path.display()))
                .runtime()?;
        }
    }
    if let Some(out) = &args.viz {
        picture(&human, &robot, &lines, method, out)?;
    }
    let mut text = String::new();
    for line in &lines {
        if args.json {
            text += &serde_json::to_string(line).context("encoding").runtime()?;
        } else {
            let partner = line
                .robot_label
                .map_or_else(|| "none".to_owned(), |l| format!("robot label {l}"));
            let p = line.position;
            text += &format!(
                "{}: person label {} -> {partner}, confidence {:.2}, at pixel ({:.0}, {:.0}), ({:.3}, {:.3}, {:.3}) m",
                line.status,
                line.human_label,
                line.confidence,
                line.centroid_px[0],
                line.centroid_px[1],
                p[0],
                p[1],
                p[2]
            );
        }
        text.push('\n');
    }
    if !args.json && lines.is_empty() {
        text = "no objects in the person's view\n".to_owned();
    }
    stdout::print(&text)
}

/// Segments (where the folder has no masks) and measures one loaded frame.
fn view(
    images: RgbdImages,
    dir: &Path,
    segmenter: &mut Segmenter,
    front_end: &mut FrontEnd,
) -> Result<View, Failure> {
    let mut up = None;
    let labels = match &images.masks {
        Some(masks) => masks.clone(),
        None => {
            let mut labels = LabelImage::new(1, 1);
            let frame = RgbdFrame {
                colour: &images.colour,
                depth: &images.depth,
                intrinsics: images.camera.intrinsics,
                up: None,
            };
            let result = segmenter
                .segment(&frame, &mut labels)
                .with_context(|| format!("segmenting {}", dir.display()))
                .bad_input()?;
            match result {
                Segmentation::Objects { plane, .. } => up = Some(plane.normal),
                Segmentation::NoSupport(reason) => {
                    tracing::warn!("{}: {reason}: 0 objects", dir.display());
                }
            }
            labels
        }
    };
    let masks = label_masks(&labels);
    let front_masks: Vec<Mask<'_>> = masks
        .iter()
        .map(|m| Mask {
            id: u64::from(m.label),
            pixels: &m.pixels,
        })
        .collect();
    let frame = Frame {
        colour: &images.colour,
        depth: &images.depth,
        intrinsics: images.camera.intrinsics,
        masks: &front_masks,
    };
    let mut detections = Vec::new();
    let skipped = front_end
        .process(&frame, &mut detections)
        .with_context(|| format!("measuring {}", dir.display()))
        .bad_input()?;
    tracing::info!(
        frame = %dir.display(),
        objects = detections.len(),
        too_small = skipped.too_small,
        no_depth = skipped.no_depth,
        "measured"
    );
    Ok(View {
        images,
        labels,
        masks,
        detections,
        up,
    })
}

fn graph(view: &View, limits: &Limits) -> anyhow::Result<SceneGraph> {
    let objects = view
        .detections
        .iter()
        .map(|d| SceneObject::new(d.id, d.position, d.feature.to_vec()).with_sigma(d.sigma))
        .collect();
    Ok(SceneGraph::new(objects, None, limits)?.with_up(view.up)?)
}

/// Every person-side object's answer, in label order.
fn answer(
    human: &View,
    robot: &View,
    method: Method,
    config: &Config,
) -> Result<Vec<AnswerLine>, Failure> {
    let rule = config.matcher.ok_rule();
    let limits = Limits {
        require_objects: false,
        ..config.scene.limits()
    };
    let solution = if human.detections.is_empty() || robot.detections.is_empty() {
        None
    } else {
        let h = graph(human, &limits).bad_input()?;
        let r = graph(robot, &limits).bad_input()?;
        Some(solve(&h, &r, method, &config.matching).runtime()?)
    };
    Ok(human
        .detections
        .iter()
        .enumerate()
        .map(|(row, d)| {
            let (partner, confidence, status) = match &solution {
                Some(s) => row_answer(s, row, &rule),
                // Nothing on the robot's side: surely no partner.
                None => (None, 1.0, Verdict::NoMatch),
            };
            let label = label_of(d.id);
            AnswerLine {
                human_label: label,
                robot_label: partner.map(|j| label_of(robot.detections[j].id)),
                status: status_name(status),
                confidence,
                centroid_px: human
                    .masks
                    .iter()
                    .find(|m| m.label == label)
                    .map_or([0.0; 2], LabelMask::centroid),
                position: d.position,
            }
        })
        .collect())
}

fn solve(
    human: &SceneGraph,
    robot: &SceneGraph,
    method: Method,
    params: &Params,
) -> anyhow::Result<Solution> {
    let problem = Problem::new(human, robot, params.beta)?;
    Ok(solve_with(
        method,
        &problem,
        params,
        SolveOptions::default(),
    )?)
}

/// Row `row`'s partner (a robot detection's index), confidence and the
/// status the live matcher gives it (as `vref eval --answers` does).
fn row_answer(solution: &Solution, row: usize, rule: &OkRule) -> (Option<usize>, f64, Verdict) {
    let partner = solution.assignment.get(row).copied().flatten();
    let confidence = solution.confidence.get(row).copied().unwrap_or(0.0);
    (partner, confidence, solution.verdict(row, confidence, rule))
}

/// Detection ids are the labels they were measured from.
fn label_of(id: u64) -> u16 {
    u16::try_from(id).unwrap_or(u16::MAX)
}

fn status_name(status: Verdict) -> &'static str {
    match status {
        Verdict::Ok => "ok",
        Verdict::Ambiguous => "ambiguous",
        Verdict::NoMatch => "no_match",
    }
}

fn picture(
    human: &View,
    robot: &View,
    lines: &[AnswerLine],
    method: Method,
    out: &Path,
) -> Result<(), Failure> {
    fn image(v: &View) -> ViewImage<'_> {
        let objects = v
            .detections
            .iter()
            .filter_map(|d| {
                let mask = v.masks.iter().find(|m| u64::from(m.label) == d.id)?;
                Some(ImageObject {
                    id: d.id,
                    centre: mask.centroid(),
                    outline: vref_import::outline(&mask.pixels),
                })
            })
            .collect();
        let (width, height) = v.images.colour.dimensions();
        ViewImage {
            rgb: v.images.colour.as_raw(),
            width,
            height,
            objects,
        }
    }
    let answers: Vec<Answer> = lines
        .iter()
        .map(|l| Answer {
            human: u64::from(l.human_label),
            robot: l.robot_label.map(u64::from),
            status: match l.status {
                "ok" => AnswerStatus::Ok,
                "ambiguous" => AnswerStatus::Ambiguous,
                _ => AnswerStatus::NoMatch,
            },
        })
        .collect();
    let ok = lines.iter().filter(|l| l.status == "ok").count();
    let title = format!(
        "vref match   ·   method {}   ·   {ok} of {} person-side objects ok",
        method.name(),
        lines.len()
    );
    let (h, r) = (image(human), image(robot));
    AnswerPicture::new(&title, &h, &r, &answers)
        .save(out)
        .with_context(|| format!("drawing {}", out.display()))
        .runtime()?;
    tracing::info!(out = %out.display(), "picture written");
    Ok(())
}
