//! `vref view`: the matcher's decision in Foxglove (crate vref-view).

use std::path::Path;
use std::sync::Arc;

use anyhow::Context;
use vref_config::Config;
use vref_feed::BopWorld;
use vref_logging::exit::{Blame, Failure};
use vref_view::images::Images;
use vref_view::{Counts, Started, ViewError, ViewOptions};

use crate::cli::ViewArgs;
use crate::stdout;

pub fn run(args: &ViewArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let images = match &args.images {
        Some(dir) => Some(load_images(&config, dir)?),
        None => None,
    };
    let options = ViewOptions {
        listen: (!args.no_listen).then_some(args.listen),
        mcap: args.mcap.clone(),
        duration: args.duration,
        scene_rate_hz: args.scene_rate,
        answer_rate_hz: args.answer_rate,
        images,
    };
    let ip = args.listen.ip();
    let counts = vref_view::run(&config.ipc, &options, |started: &Started| {
        if let Some(port) = started.port {
            // Tests and scripts read the port from this line.
            stdout::print(&format!(
                "serving ws://{ip}:{port} (Foxglove: Open connection, Foxglove WebSocket)\n"
            ))
            .ok();
        }
        tracing::info!(namespace = %config.ipc.namespace, "viewing");
    })
    .map_err(blame)?;
    if let Some(path) = &args.mcap {
        stdout::print(&format!("{}: {}\n", path.display(), describe(&counts)))?;
    }
    Ok(())
}

/// The images of every scene the feeds show with `--source bop:DIR`: the
/// scenes measured as the feeds measure them (same folder, same
/// `[perception]` and `[scene]` settings), so that the track ids agree.
pub fn load_images(config: &Config, dir: &Path) -> Result<Arc<Images>, Failure> {
    // The feeds' hold time does not matter here: the viewer follows the
    // snapshots' track ids, not a schedule.
    let world = BopWorld::load(dir, None, config.perception, config.scene.limits(), 1.0)
        .with_context(|| format!("--images bop:{}", dir.display()))
        .bad_input()?;
    let images = vref_view::load_bop_images(&world, config.perception.image_limit())
        .with_context(|| format!("--images bop:{}", dir.display()))
        .bad_input()?;
    tracing::info!(scenes = images.scenes().len(), "images loaded");
    Ok(Arc::new(images))
}

/// A file that cannot be created is the caller's to fix; anything else
/// broke while running.
pub fn blame(e: ViewError) -> Failure {
    match e {
        ViewError::Create { .. } => Failure::BadInput(e.into()),
        _ => Failure::Runtime(e.into()),
    }
}

/// Messages by channel, in words.
pub fn describe(c: &Counts) -> String {
    use vref_record::WireChannel::{Decision, Gesture, HumanSnapshot, RobotSnapshot};
    format!(
        "{} messages (robot snapshots {}, human snapshots {}, rays {}, decisions {}; \
         scene updates {}, transforms {}, answers {}, statistics {}, \
         images {}, calibrations {}, image annotations {})",
        c.total(),
        c.wire(RobotSnapshot),
        c.wire(HumanSnapshot),
        c.wire(Gesture),
        c.wire(Decision),
        c.scenes,
        c.transforms,
        c.answers,
        c.stats,
        c.images,
        c.images,
        c.annotations
    )
}
