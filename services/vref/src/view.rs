//! `vref view`: the matcher's decision in Foxglove (crate vref-view).

use vref_config::Config;
use vref_view::{Counts, Started, ViewError, ViewOptions};

use crate::cli::ViewArgs;
use crate::failure::{Blame, Failure};
use crate::stdout;

pub fn run(args: &ViewArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let options = ViewOptions {
        listen: (!args.no_listen).then_some(args.listen),
        mcap: args.mcap.clone(),
        duration: args.duration,
        scene_rate_hz: args.scene_rate,
        answer_rate_hz: args.answer_rate,
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
         scene updates {}, transforms {}, answers {}, statistics {})",
        c.total(),
        c.wire(RobotSnapshot),
        c.wire(HumanSnapshot),
        c.wire(Gesture),
        c.wire(Decision),
        c.scenes,
        c.transforms,
        c.answers,
        c.stats
    )
}
