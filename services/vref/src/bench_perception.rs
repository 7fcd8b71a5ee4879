//! `vref bench perception`: time per image of the perception front end on
//! BOP datasets, apart from decoding the image files.

use std::time::Instant;

use anyhow::Context;
use vref_config::Config;
use vref_import::{BopDataset, BopSceneDir, BopView, datasets_in, track_ids};
use vref_logging::exit::{Blame, Failure};
use vref_perception::{Detection, Frame, FrontEnd, FrontEndSettings, ImageLimit, Mask};

use crate::cli::BenchPerceptionArgs;
use crate::stdout;

/// Timings of one dataset.
#[derive(Debug, serde::Serialize)]
struct Timing {
    dataset: String,
    images: usize,
    /// Objects measured over all images (one pass).
    objects: usize,
    /// Most masks in one image.
    max_masks: usize,
    /// The front end alone (decoded images in memory).
    median_us: f64,
    p99_us: f64,
    /// Decoding one image's files (colour, depth, every mask).
    decode_median_us: f64,
    decode_p99_us: f64,
    repeats: u64,
}

pub fn perception(args: &BenchPerceptionArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let settings = config.perception;
    for dir in datasets_in(&args.dataset, &args.split).bad_input()? {
        let dataset = BopDataset::open(&dir, &args.split).bad_input()?;
        let timing = time_dataset(
            &dataset,
            args,
            [settings.robot(), settings.human()],
            settings.image_limit(),
        )?;
        let line = if args.json {
            serde_json::to_string(&timing)
                .context("encoding")
                .runtime()?
        } else {
            format!(
                "{}: {} images, {} objects (at most {} masks an image), front end median {:.0} us, p99 {:.0} us; decoding median {:.0} us, p99 {:.0} us ({} repeats)",
                timing.dataset,
                timing.images,
                timing.objects,
                timing.max_masks,
                timing.median_us,
                timing.p99_us,
                timing.decode_median_us,
                timing.decode_p99_us,
                timing.repeats
            )
        };
        stdout::print(&format!("{line}\n"))?;
    }
    Ok(())
}

fn time_dataset(
    dataset: &BopDataset,
    args: &BenchPerceptionArgs,
    settings: [FrontEndSettings; 2],
    limit: ImageLimit,
) -> Result<Timing, Failure> {
    let mut views: Vec<(BopView, Vec<u64>, usize)> = Vec::new();
    let mut decode_us = Vec::new();
    for scene in dataset.scenes() {
        for (camera, image) in [(0, args.robot_image), (1, args.human_image)] {
            for _ in 0..args.repeats {
                let start = Instant::now();
                load(scene, image, limit)?;
                decode_us.push(start.elapsed().as_secs_f64() * 1e6);
            }
            let view = load(scene, image, limit)?;
            let ids = track_ids(scene.id, image, view.masks.len(), 0);
            views.push((view, ids, camera));
        }
    }
    let mut front_ends = settings.map(FrontEnd::new);
    let mut out: Vec<Detection> = Vec::new();
    let mut front_us = Vec::new();
    let mut objects = 0;
    for pass in 0..args.repeats {
        for (view, ids, camera) in &views {
            let masks: Vec<Mask<'_>> = view
                .masks
                .iter()
                .zip(ids)
                .map(|(pixels, &id)| Mask { id, pixels })
                .collect();
            let frame = Frame {
                colour: &view.colour,
                depth: &view.depth,
                intrinsics: view.intrinsics,
                masks: &masks,
            };
            let start = Instant::now();
            front_ends[*camera]
                .process(&frame, &mut out)
                .context("front end")
                .bad_input()?;
            front_us.push(start.elapsed().as_secs_f64() * 1e6);
            if pass == 0 {
                objects += out.len();
            }
        }
    }
    Ok(Timing {
        dataset: dataset.name().to_owned(),
        images: views.len(),
        objects,
        max_masks: views
            .iter()
            .map(|(v, _, _)| v.masks.len())
            .max()
            .unwrap_or(0),
        median_us: percentile(&mut front_us, 0.5),
        p99_us: percentile(&mut front_us, 0.99),
        decode_median_us: percentile(&mut decode_us, 0.5),
        decode_p99_us: percentile(&mut decode_us, 0.99),
        repeats: args.repeats,
    })
}

fn load(scene: &BopSceneDir, image: u32, limit: ImageLimit) -> Result<BopView, Failure> {
    scene.load_view(image, limit).bad_input()
}

/// Nearest rank (vref_measure's one definition); 0 without values.
fn percentile(values: &mut [f64], q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    vref_measure::percentile(values, q).unwrap_or(0.0)
}
