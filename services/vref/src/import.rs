use std::fs::File;
use std::io::{BufWriter, Write};

use anyhow::Context;
use anyhow::anyhow;
use vref_config::Config;
use vref_import::{BopDataset, BopImport, BopOptions, CmuHouse, CmuHouseOptions};
use vref_logging::exit::{Blame, Failure};
use vref_scene::{DatasetWriter, ScenePair};

use crate::cli::{BopArgs, CmuHouseArgs};

pub fn cmu_house(args: &CmuHouseArgs) -> Result<(), Failure> {
    let house = CmuHouse::load(&args.dir).bad_input()?;
    let options = CmuHouseOptions {
        gap: args.gap,
        delaunay: args.delaunay,
        features: args.features,
        keep: args.keep,
        seed: args.seed,
    };
    let pairs = house.pairs(&options).bad_input()?;
    write_dataset(&pairs, args.out.as_deref())?;
    tracing::info!(
        scenes = pairs.len(),
        frames = house.frames(),
        "imported CMU House"
    );
    Ok(())
}

pub fn bop(args: &BopArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let mut perception = config.perception;
    if let Some(n) = args.min_pixels {
        perception.min_pixels = n;
    }
    perception.validate().context("--min-pixels").bad_input()?;
    let dataset = BopDataset::open(&args.dir, &args.split).bad_input()?;
    let options = BopOptions {
        robot_image: args.robot_image,
        human_image: args.human_image,
        perception,
        world_up: args.world_up,
    };
    let import = if args.segment {
        config
            .segmentation
            .validate()
            .context("[segmentation]")
            .bad_input()?;
        BopImport::run_segmented(&dataset, &options, &config.segmentation)
    } else {
        BopImport::run(&dataset, &options)
    };
    let no_support = import.no_support();
    for (scene, reason) in &no_support {
        tracing::warn!("scene {scene}: one view has 0 objects: {reason}");
    }
    if args.world_up.is_some() {
        for warning in import.scenes.iter().filter_map(|s| s.missing_up()) {
            tracing::warn!("{warning}");
        }
    }
    let skipped = import.skipped();
    let BopImport { scenes, failed } = import;
    let failures = failed.len();
    for (scene, error) in failed {
        tracing::warn!("scene {scene} skipped: {:#}", anyhow::Error::new(error));
    }
    let limits = config.scene.limits();
    // With vref's own segments a view can hold no object at all (no
    // plane, nothing measurable): that scene is left out, not the import.
    let mut pairs: Vec<ScenePair> = Vec::with_capacity(scenes.len());
    let mut left_out = 0;
    for scene in &scenes {
        match scene.pair(&limits) {
            Ok(pair) => pairs.push(pair),
            Err(e) if args.segment => {
                left_out += 1;
                tracing::warn!("scene {} skipped: {:#}", scene.name, anyhow::Error::new(e));
            }
            Err(e) => return Err(e).bad_input(),
        }
    }
    if pairs.is_empty() {
        return Err(anyhow!(
            "{}: none of its {failures} scenes could be imported",
            args.dir.display(),
        ))
        .bad_input();
    }
    write_dataset(&pairs, args.out.as_deref())?;
    tracing::warn!(
        scenes = pairs.len(),
        scenes_skipped = failures + left_out,
        masks_too_small = skipped.too_small,
        masks_without_depth = skipped.no_depth,
        masks_over_the_whole_frame = skipped.whole_frame,
        views_without_support = no_support.len(),
        "imported {}",
        dataset.name()
    );
    Ok(())
}

/// Writes `pairs` to `out` (renamed into place, so that a failed import
/// never leaves a truncated dataset behind) or to stdout.
fn write_dataset(pairs: &[ScenePair], out: Option<&std::path::Path>) -> Result<(), Failure> {
    match out {
        Some(path) => {
            let partial = path.with_extension("jsonl.tmp");
            let file = File::create(&partial)
                .with_context(|| format!("creating {}", partial.display()))
                .runtime()?;
            write_all(pairs, BufWriter::new(file)).runtime()?;
            std::fs::rename(&partial, path)
                .with_context(|| format!("renaming {} to {}", partial.display(), path.display()))
                .runtime()?;
        }
        None => write_all(pairs, std::io::stdout().lock()).runtime()?,
    }
    Ok(())
}

fn write_all<W: Write>(pairs: &[ScenePair], output: W) -> anyhow::Result<()> {
    let mut writer = DatasetWriter::new(output);
    for pair in pairs {
        writer.write(pair)?;
    }
    writer.finish()?;
    Ok(())
}
