//! Writes `rigid`'s answers (`RowAnswer` JSON lines, with margin, fit and
//! significance) on the data sets of docs/method.md, for choosing the
//! coincidence constants on the training files and reporting on the rest
//! (the same `Evaluation` as `vref eval`), one `NAME.jsonl` per set in
//! OUT_DIR:
//!
//! `cargo run --release -p vref-research --example rigid_answers -- OUT_DIR`
//!
//! Training files by default (sim seeds 100-109 pooled per preset, or per
//! seed with `--per-seed`; external lines 1-20; BOP scenes 0-5), reporting
//! files with `--report`; unrelated views of each (seed 11 for training
//! clouds, 12 for reporting); `--only real|null`; `--no-gate` turns the
//! coincidence rule off (`chance_rule = false`). The external and BOP files
//! are read from `../shared/data/external` and `../data` beside the
//! repository.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Parser;
use vref_match::{Evaluation, Method, Params};
use vref_scene::{Limits, ScenePair, read_dataset_file};
use vref_sim::unrelated::{across_scenes, random_clouds, shuffled};
use vref_sim::{Generator, Preset};

/// The folder that holds the repository.
const BESIDE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../..");

#[derive(Debug, Parser)]
struct Args {
    /// Folder the answer files are written to (created if missing).
    out: PathBuf,
    /// The reporting files instead of the training files.
    #[arg(long)]
    report: bool,
    /// One file per sim seed instead of one pooled per preset.
    #[arg(long)]
    per_seed: bool,
    /// Only the real sets (`real`) or only the unrelated views (`null`).
    #[arg(long, value_name = "real|null")]
    only: Option<String>,
    /// Turn the coincidence rule off.
    #[arg(long)]
    no_gate: bool,
}

fn dump(out: &Path, name: &str, pairs: &[ScenePair], params: &Params) -> anyhow::Result<()> {
    let mut evaluation = Evaluation::new(&[Method::Rigid], *params)?;
    let t = std::time::Instant::now();
    for pair in pairs {
        evaluation.add(pair)?;
    }
    let path = out.join(format!("{name}.jsonl"));
    let file = File::create(&path).with_context(|| format!("creating {}", path.display()))?;
    let mut file = BufWriter::new(file);
    for a in evaluation.answers(Method::Rigid) {
        serde_json::to_writer(&mut file, a)?;
        file.write_all(b"\n")?;
    }
    file.flush()?;
    eprintln!(
        "{name}: {} scenes {:.1}s",
        pairs.len(),
        t.elapsed().as_secs_f64()
    );
    Ok(())
}

fn read(path: &str) -> anyhow::Result<Vec<ScenePair>> {
    read_dataset_file(path.as_ref(), Limits::default()).with_context(|| format!("reading {path}"))
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let mut params = Params::default();
    if args.no_gate {
        params.rigid.chance_rule = false;
    }
    let (report, per_seed) = (args.report, args.per_seed);
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let mut real: Vec<(String, Vec<ScenePair>)> = Vec::new();
    let seeds: Vec<u64> = if report {
        (1..=5).collect()
    } else {
        (100..=109).collect()
    };
    for preset in [Preset::Moi, Preset::Mrc] {
        let mut all = Vec::new();
        for &seed in &seeds {
            let g = Generator::new(preset.config(), seed)?;
            let pairs = g
                .scenes(30)
                .map(|s| s.map(|s| s.pair))
                .collect::<Result<Vec<_>, _>>()?;
            if report || per_seed {
                real.push((format!("{preset:?}{seed}"), pairs.clone()));
            }
            all.push(pairs);
        }
        if !report && !per_seed {
            real.push((format!("{preset:?}-train"), all.concat()));
        }
    }
    for family in ["moi", "mrc"] {
        let pairs = read(&format!("{BESIDE}/shared/data/external/{family}-ext.jsonl"))?;
        let (train, rep) = pairs.split_at(20.min(pairs.len()));
        real.push((
            format!("{family}-ext"),
            if report { rep.to_vec() } else { train.to_vec() },
        ));
    }
    for family in ["table", "floor"] {
        let mut keep = Vec::new();
        for pair in read(&format!("{BESIDE}/data/bop-{family}.jsonl"))? {
            let k: u32 = pair
                .name
                .rsplit('/')
                .next()
                .and_then(|k| k.parse().ok())
                .with_context(|| format!("scene {:?} has no number", pair.name))?;
            if (report && (6..=11).contains(&k)) || (!report && k <= 5) {
                keep.push(pair);
            }
        }
        real.push((format!("bop-{family}"), keep));
    }
    let only = args.only.unwrap_or_default();
    for (name, pairs) in &real {
        if only.is_empty() || only.contains("real") {
            dump(&args.out, name, pairs, &params)?;
        }
    }
    if !(only.is_empty() || only.contains("null")) {
        return Ok(());
    }
    for (name, pairs) in &real {
        let first: Vec<ScenePair> = if name.ends_with("-train") {
            pairs[..30.min(pairs.len())].to_vec()
        } else {
            pairs.clone()
        };
        dump(
            &args.out,
            &format!("null-{name}-across"),
            &across_scenes(&first)?,
            &params,
        )?;
        dump(
            &args.out,
            &format!("null-{name}-shuffled"),
            &shuffled(&first, 7)?,
            &params,
        )?;
    }
    let seed = if report { 12 } else { 11 };
    for objects in [8, 32, 64, 128, 256] {
        dump(
            &args.out,
            &format!("null-clouds-{objects}"),
            &random_clouds(20, objects, 60, seed)?,
            &params,
        )?;
    }
    Ok(())
}
