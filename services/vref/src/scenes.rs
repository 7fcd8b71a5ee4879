use std::ffi::OsString;
use std::fs::File;
use std::io::{BufWriter, ErrorKind, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow};
use vref_scene::DatasetWriter;
use vref_sim::{Generator, Preset};

use crate::cli::ScenesArgs;
use crate::failure::{Blame, Failure};

pub fn run(args: &ScenesArgs) -> Result<(), Failure> {
    let preset: Preset = args.preset.parse().context("--preset").bad_input()?;
    if args.count == 0 {
        return Err(anyhow!("--count: must be at least 1")).bad_input();
    }
    let generator = Generator::new(preset.config(), args.seed)
        .with_context(|| format!("preset {preset}"))
        .bad_input()?
        .named(preset.name());
    match &args.out {
        Some(path) => write_file(&generator, args.count, path)?,
        None => match write_scenes(&generator, args.count, std::io::stdout().lock()) {
            // A reader that went away (`vref scenes ... | head`) ends the
            // output quietly, as other Unix tools do.
            Err(e) if is_broken_pipe(&e) => {}
            result => result.runtime()?,
        },
    }
    tracing::info!(
        preset = preset.name(),
        count = args.count,
        seed = args.seed,
        "generated scenes"
    );
    Ok(())
}

/// Writes beside the target and renames, so that a failed run never leaves
/// a truncated dataset behind.
fn write_file(generator: &Generator, count: u64, path: &Path) -> Result<(), Failure> {
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

fn write_scenes<W: Write>(generator: &Generator, count: u64, output: W) -> anyhow::Result<()> {
    let mut writer = DatasetWriter::new(output);
    for scene in generator.scenes(count) {
        writer.write(&scene?.pair)?;
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
