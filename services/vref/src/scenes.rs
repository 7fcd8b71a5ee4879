use std::ffi::OsString;
use std::fs::File;
use std::io::{BufWriter, ErrorKind, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow};
use vref_logging::exit::{Blame, Failure};
use vref_scene::{DatasetWriter, ScenePair};
use vref_sim::{Generator, Preset, RigidScene};

use crate::cli::ScenesArgs;

/// Where scene pairs come from: a generator preset, or the solver
/// benchmark's rigid scenes.
enum Source {
    Preset(Box<Generator>),
    Rigid { objects: usize, seed: u64 },
}

impl Source {
    fn scenes(&self, count: u64) -> Box<dyn Iterator<Item = anyhow::Result<ScenePair>> + '_> {
        match self {
            Source::Preset(generator) => Box::new(
                generator
                    .scenes(count)
                    .map(|s| s.map(|s| s.pair).map_err(anyhow::Error::from)),
            ),
            Source::Rigid { objects, seed } => Box::new((0..count).map(move |k| {
                let scene = RigidScene::new(*objects, seed.wrapping_add(k))?;
                Ok(scene.pair(format!("rigid-{objects}-{k}"))?)
            })),
        }
    }
}

pub fn run(args: &ScenesArgs) -> Result<(), Failure> {
    if args.count == 0 {
        return Err(anyhow!("--count: must be at least 1")).bad_input();
    }
    if args.up_vectors.is_some() && args.preset == "rigid" {
        return Err(anyhow!("--up-vectors applies to moi and mrc only")).bad_input();
    }
    let source = match (args.preset.as_str(), args.objects) {
        ("rigid", Some(objects)) => {
            // Checked here so that a bad size is bad input, not a failure
            // half-way through the file.
            RigidScene::new(objects, args.seed)
                .context("--objects")
                .bad_input()?;
            Source::Rigid {
                objects,
                seed: args.seed,
            }
        }
        ("rigid", None) => {
            return Err(anyhow!("--preset rigid needs --objects")).bad_input();
        }
        (_, Some(_)) => {
            return Err(anyhow!("--objects applies to --preset rigid only")).bad_input();
        }
        (name, None) => {
            let preset: Preset = name.parse().context("--preset").bad_input()?;
            let mut generator = Generator::new(preset.config(), args.seed)
                .with_context(|| format!("preset {preset}"))
                .bad_input()?
                .named(preset.name());
            if let Some(error) = args.up_vectors {
                generator = generator
                    .with_up_vectors(error)
                    .context("--up-vectors")
                    .bad_input()?;
            }
            Source::Preset(Box::new(generator))
        }
    };
    let generator = &source;
    match &args.out {
        Some(path) => write_file(generator, args.count, path)?,
        None => match write_scenes(generator, args.count, std::io::stdout().lock()) {
            // A reader that went away (`vref scenes ... | head`) ends the
            // output quietly, as other Unix tools do.
            Err(e) if is_broken_pipe(&e) => {}
            result => result.runtime()?,
        },
    }
    tracing::info!(
        preset = args.preset,
        count = args.count,
        seed = args.seed,
        "generated scenes"
    );
    Ok(())
}

/// Writes beside the target and renames, so that a failed run never leaves
/// a truncated dataset behind.
fn write_file(generator: &Source, count: u64, path: &Path) -> Result<(), Failure> {
    let mut name = OsString::from(path.as_os_str());
    name.push(".tmp");
    let partial = PathBuf::from(name);
    let written = File::create(&partial)
        .with_context(|| format!("creating {}", partial.display()))
        .and_then(|file| write_scenes(generator, count, BufWriter::new(file)))
        .and_then(|()| {
            std::fs::rename(&partial, path)
                .with_context(|| format!("renaming {} to {}", partial.display(), path.display()))
        });
    if written.is_err() {
        // Best effort: the error being reported matters more than this one.
        let _ = std::fs::remove_file(&partial);
    }
    written.runtime()
}

fn write_scenes<W: Write>(generator: &Source, count: u64, output: W) -> anyhow::Result<()> {
    let mut writer = DatasetWriter::new(output);
    for pair in generator.scenes(count) {
        writer.write(&pair?)?;
    }
    writer.finish()?;
    Ok(())
}

fn is_broken_pipe(error: &anyhow::Error) -> bool {
    error.chain().any(|cause| {
        cause
            .downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == ErrorKind::BrokenPipe)
    })
}
