//! Writes dataset files of views with nothing in common (every partner a
//! matcher gives is wrong): each input file's scenes paired across scenes
//! (`NAME-across.jsonl`) and with the human positions shuffled per axis
//! (`NAME-shuffled.jsonl`), and random clouds of 8 to 256 objects
//! (`clouds-N.jsonl`, 20 pairs each, drawn with `SEED`). See
//! `vref_sim::unrelated`.
//!
//! `cargo run --release -p vref-research --example unrelated -- SEED OUT_DIR FILE.jsonl...`

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use anyhow::Context;
use vref_scene::{DatasetWriter, Limits, ScenePair, read_dataset_file};
use vref_sim::unrelated::{across_scenes, random_clouds, shuffled};

fn write(path: &Path, pairs: &[ScenePair]) -> anyhow::Result<()> {
    let file = File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut writer = DatasetWriter::new(BufWriter::new(file));
    for pair in pairs {
        writer.write(pair)?;
    }
    writer.finish()?;
    Ok(())
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: unrelated SEED OUT_DIR FILE.jsonl...";
    let (seed, rest) = args.split_first().context(usage)?;
    let seed: u64 = seed.parse().context(usage)?;
    let (out, files) = rest.split_first().context(usage)?;
    let out = Path::new(out);
    std::fs::create_dir_all(out)?;
    for file in files {
        let pairs = read_dataset_file(file.as_ref(), Limits::default())?;
        let stem = Path::new(file)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("scenes");
        write(
            &out.join(format!("{stem}-across.jsonl")),
            &across_scenes(&pairs)?,
        )?;
        write(
            &out.join(format!("{stem}-shuffled.jsonl")),
            &shuffled(&pairs, 7)?,
        )?;
    }
    for objects in [8, 32, 64, 128, 256] {
        let clouds = random_clouds(20, objects, 60, seed)?;
        write(&out.join(format!("clouds-{objects}.jsonl")), &clouds)?;
    }
    Ok(())
}
