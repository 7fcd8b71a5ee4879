use std::fs::File;
use std::io::{BufWriter, Write};

use anyhow::Context;
use vref_import::{CmuHouse, CmuHouseOptions};
use vref_scene::DatasetWriter;

use crate::cli::CmuHouseArgs;
use crate::failure::{Blame, Failure};

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
    match &args.out {
        Some(path) => {
            // Written beside the target and renamed, so that a failed
            // import never leaves a truncated dataset behind.
            let partial = path.with_extension("jsonl.tmp");
            let file = File::create(&partial)
                .with_context(|| format!("creating {}", partial.display()))
                .runtime()?;
            write_all(&pairs, BufWriter::new(file)).runtime()?;
            std::fs::rename(&partial, path)
                .with_context(|| format!("renaming {} to {}", partial.display(), path.display()))
                .runtime()?;
        }
        None => write_all(&pairs, std::io::stdout().lock()).runtime()?,
    }
    tracing::info!(
        scenes = pairs.len(),
        frames = house.frames(),
        "imported CMU House"
    );
    Ok(())
}

fn write_all<W: Write>(pairs: &[vref_scene::ScenePair], output: W) -> anyhow::Result<()> {
    let mut writer = DatasetWriter::new(output);
    for pair in pairs {
        writer.write(pair)?;
    }
    writer.finish()?;
    Ok(())
}
