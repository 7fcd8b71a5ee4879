//! `vref bench segment`: time per frame of the segmenter (single thread,
//! images decoded beforehand) and, where a scene has its ground truth,
//! the scores of ../shared/data/osd/PROVENANCE.md's protocol.

use std::time::Instant;

use anyhow::Context;
use vref_config::Config;
use vref_logging::exit::{Blame, Failure};
use vref_perception::segment::score::{ImageScore, MeanScore, score_image};
use vref_perception::{LabelImage, RgbdFrame, Segmentation, Segmenter};

use crate::cli::BenchSegmentArgs;
use crate::stdout;
use vref_perception::folder::{
    Camera, DEPTH_FILE, RgbdImages, camera_file_of, colour_file, frame_dirs, natural_key,
};

/// One scene's result.
#[derive(Debug, serde::Serialize)]
struct SceneLine {
    scene: String,
    objects: usize,
    no_support: Option<String>,
    #[serde(flatten)]
    score: Option<ImageScore>,
    median_us: f64,
}

/// Mean scores of a group of scenes.
#[derive(Debug, serde::Serialize)]
struct Group {
    group: String,
    images: usize,
    overlap_p: f64,
    overlap_r: f64,
    overlap_f: f64,
    boundary_p: f64,
    boundary_r: f64,
    boundary_f: f64,
    p75: f64,
    /// The worst scene's overlap F.
    min_overlap_f: f64,
}

impl Group {
    fn of(group: &str, scores: &[ImageScore]) -> Self {
        let mean = MeanScore::of(scores);
        Self {
            group: group.to_owned(),
            images: mean.images,
            overlap_p: mean.overlap.precision,
            overlap_r: mean.overlap.recall,
            overlap_f: mean.overlap.f,
            boundary_p: mean.boundary.precision,
            boundary_r: mean.boundary.recall,
            boundary_f: mean.boundary.f,
            p75: mean.p75,
            min_overlap_f: scores.iter().map(|s| s.overlap.f).fold(1.0, f64::min),
        }
    }
}

#[derive(Debug, serde::Serialize)]
struct Summary {
    dataset: String,
    images: usize,
    /// Scenes with a ground truth (the scores are their means).
    scored: usize,
    /// Scenes where no supporting plane was found.
    no_support: usize,
    median_us: f64,
    p99_us: f64,
    repeats: u64,
    /// Means over the scored scenes (absent without any ground truth).
    #[serde(flatten)]
    all: Option<Means>,
    groups: Vec<Group>,
}

/// The summary's scores, the `all` group without its name and count.
#[derive(Debug, serde::Serialize)]
struct Means {
    overlap_p: f64,
    overlap_r: f64,
    overlap_f: f64,
    boundary_p: f64,
    boundary_r: f64,
    boundary_f: f64,
    p75: f64,
    min_overlap_f: f64,
}

impl From<&Group> for Means {
    fn from(g: &Group) -> Self {
        Self {
            overlap_p: g.overlap_p,
            overlap_r: g.overlap_r,
            overlap_f: g.overlap_f,
            boundary_p: g.boundary_p,
            boundary_r: g.boundary_r,
            boundary_f: g.boundary_f,
            p75: g.p75,
            min_overlap_f: g.min_overlap_f,
        }
    }
}

/// The OSD learn set's scene kinds (PROVENANCE.md): learn 0-16 boxes,
/// 17-24 stacked boxes, 25-32 occluded, 33-44 cylinders. Other names have
/// no kind.
fn osd_kind(name: &str) -> Option<&'static str> {
    let n: u32 = name.strip_prefix("learn")?.parse().ok()?;
    Some(match n {
        0..=16 => "boxes",
        17..=24 => "stacked",
        25..=32 => "occluded",
        33..=44 => "cylinders",
        _ => return None,
    })
}

/// The held-aside scenes: a trailing number that is 0 mod 5.
fn held_aside(name: &str) -> Option<bool> {
    let (_, number, _) = natural_key(name);
    (number != u64::MAX).then_some(number % 5 == 0)
}

pub fn segment(args: &BenchSegmentArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let camera_path = match &args.camera {
        Some(path) => path.clone(),
        None => camera_file_of(&args.dataset).bad_input()?,
    };
    let (camera, unread) = Camera::read(&camera_path).bad_input()?;
    vref_feed::warn_unread(&unread, &camera_path.display().to_string());
    let mut frames: Vec<(String, RgbdImages)> = Vec::new();
    for (name, dir) in frame_dirs(&args.dataset).bad_input()? {
        // The scene's ground-truth labels load as its masks: checked
        // against the colour image's size like any.
        let truth = dir.join("label.png");
        let images = RgbdImages::load_files(
            &colour_file(&dir),
            &dir.join(DEPTH_FILE),
            truth.is_file().then_some(truth.as_path()),
            camera,
            config.perception.image_limit(),
        )
        .bad_input()?;
        frames.push((name, images));
    }
    let mut segmenter = Segmenter::new(config.segmentation);
    let mut labels = LabelImage::new(1, 1);
    let mut all_us = Vec::new();
    let mut lines = Vec::new();
    for (name, images) in &frames {
        let truth = &images.masks;
        let frame = RgbdFrame {
            colour: &images.colour,
            depth: &images.depth,
            intrinsics: camera.intrinsics,
            up: None,
        };
        let mut us = Vec::new();
        let mut result = Segmentation::NoSupport(vref_perception::NoSupport::NoReadings {
            samples: 0,
            needed: 0,
        });
        for _ in 0..args.repeats {
            let start = Instant::now();
            result = segmenter
                .segment(&frame, &mut labels)
                .with_context(|| name.clone())
                .bad_input()?;
            us.push(start.elapsed().as_secs_f64() * 1e6);
        }
        all_us.extend_from_slice(&us);
        let score = match truth {
            Some(truth) => Some(
                score_image(
                    &labels,
                    truth,
                    labels.width(),
                    labels.height(),
                    args.first_object,
                )
                .with_context(|| name.clone())
                .bad_input()?,
            ),
            None => None,
        };
        lines.push(SceneLine {
            scene: name.clone(),
            objects: result.objects(),
            no_support: match result {
                Segmentation::NoSupport(reason) => Some(reason.to_string()),
                Segmentation::Objects { .. } => None,
            },
            score,
            median_us: percentile(&mut us, 0.5),
        });
    }
    if args.scenes {
        for line in &lines {
            let text = if args.json {
                serde_json::to_string(line).context("encoding").runtime()?
            } else {
                match &line.score {
                    Some(s) => format!(
                        "{}: {} objects ({} in the truth), overlap F {:.3}, boundary F {:.3}, %75 {:.3}, {:.0} us",
                        line.scene,
                        line.objects,
                        s.gt_objects,
                        s.overlap.f,
                        s.boundary.f,
                        s.p75,
                        line.median_us
                    ),
                    None => format!(
                        "{}: {} objects, {:.0} us",
                        line.scene, line.objects, line.median_us
                    ),
                }
            };
            stdout::print(&format!("{text}\n"))?;
        }
    }
    let scored: Vec<(&str, ImageScore)> = lines
        .iter()
        .filter_map(|l| l.score.map(|s| (l.scene.as_str(), s)))
        .collect();
    let group = |label: &str, pick: &dyn Fn(&str) -> bool| {
        let scores: Vec<ImageScore> = scored
            .iter()
            .filter(|(n, _)| pick(n))
            .map(|(_, s)| *s)
            .collect();
        (!scores.is_empty()).then(|| Group::of(label, &scores))
    };
    let all = group("all", &|_| true);
    let mut groups = Vec::new();
    for kind in ["boxes", "stacked", "occluded", "cylinders"] {
        groups.extend(group(kind, &|n| osd_kind(n) == Some(kind)));
    }
    groups.extend(group("tune (number not 0 mod 5)", &|n| {
        held_aside(n) == Some(false)
    }));
    groups.extend(group("held aside (number 0 mod 5)", &|n| {
        held_aside(n) == Some(true)
    }));
    let summary = Summary {
        dataset: args.dataset.display().to_string(),
        images: lines.len(),
        scored: scored.len(),
        no_support: lines.iter().filter(|l| l.no_support.is_some()).count(),
        median_us: percentile(&mut all_us, 0.5),
        p99_us: percentile(&mut all_us, 0.99),
        repeats: args.repeats,
        all: all.as_ref().map(Means::from),
        groups,
    };
    let text = if args.json {
        serde_json::to_string(&summary)
            .context("encoding")
            .runtime()?
    } else {
        human(&summary, all.as_ref())
    };
    stdout::print(&format!("{text}\n"))
}

fn human(s: &Summary, all: Option<&Group>) -> String {
    let mut text = format!(
        "{}: {} images ({} without a supporting plane), segmenter median {:.0} us, p99 {:.0} us ({} repeats, one thread)",
        s.dataset, s.images, s.no_support, s.median_us, s.p99_us, s.repeats
    );
    for g in all.into_iter().chain(&s.groups) {
        text.push_str(&format!(
            "\n  {:30} {:3} images  overlap P {:.3} R {:.3} F {:.3}  boundary P {:.3} R {:.3} F {:.3}  %75 {:.3}  worst overlap F {:.3}",
            g.group,
            g.images,
            g.overlap_p,
            g.overlap_r,
            g.overlap_f,
            g.boundary_p,
            g.boundary_r,
            g.boundary_f,
            g.p75,
            g.min_overlap_f
        ));
    }
    text
}

/// Nearest rank (vref_measure's one definition); 0 without values.
fn percentile(values: &mut [f64], q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    vref_measure::percentile(values, q).unwrap_or(0.0)
}
