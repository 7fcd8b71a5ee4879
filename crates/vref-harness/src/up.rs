//! `vref up`: the matcher and both synthetic feeds, running until asked to
//! stop, for clients of any language to talk to (the Python benchmark, a
//! controller being written). Under a root path and prefix of their own,
//! like every run here; the configuration the clients need is said first.

use std::path::Path;
use std::time::{Duration, Instant};

use vref_config::Config;
use vref_wire::AnswerStatus;
use vref_wire::ipc::{ReferenceClient, create_node, nap};

use crate::launch::{Run, Services, prepare};
use crate::ready::{READY_WITHIN, Readiness, ReadyError, wait_ready};
use crate::{Finished, OutputError, RunError};

/// How often the services are checked while they run.
const CHECK_EVERY: Duration = Duration::from_millis(200);

/// What `vref up` was asked for.
#[derive(Debug, Clone, Default)]
pub struct UpOptions {
    /// Objects in the synthetic world (`None`: the [feeds] preset's).
    pub objects: Option<usize>,
    /// Stop after this long (`None`: only when asked to).
    pub duration: Option<Duration>,
}

/// Starts the services from `bin_dir` with `config` isolated, says
/// `config PATH` (the file clients connect with) through `on_line`, then
/// `ready` once a latest-gesture query is answered with a partner, and
/// keeps them running until SIGINT or SIGTERM (or `options.duration`).
/// A service that exits on its own ends the run with an error naming it.
pub fn run(
    options: &UpOptions,
    config: &Config,
    bin_dir: &Path,
    on_line: &mut dyn FnMut(&str) -> Result<(), OutputError>,
) -> Result<Finished<()>, RunError> {
    let feed_args = match options.objects {
        Some(n) => vec!["--objects".to_owned(), n.to_string()],
        None => Vec::new(),
    };
    prepare(config, bin_dir, "up", "vup")?.run_system(
        &feed_args,
        |run, services| serve(options, run, services, on_line),
        |_, _| (),
    )
}

/// Says where the services are, waits for them, then until asked to stop.
fn serve(
    options: &UpOptions,
    run: &Run<'_>,
    services: &mut Services,
    on_line: &mut dyn FnMut(&str) -> Result<(), OutputError>,
) -> Result<(), RunError> {
    on_line(&format!("config {}\n", run.config_path.display())).map_err(RunError::Output)?;
    let config = run.config;
    let pid = std::process::id();
    let mut client = ReferenceClient::connect(&config.ipc, &format!("vref-up-{pid}"))?;
    wait_ready(READY_WITHIN, Duration::from_millis(100), || {
        services.ensure_running()?;
        let answered = client
            .latest_gesture(Duration::from_secs(1))
            .is_ok_and(|a| matches!(a.status(), AnswerStatus::Ok | AnswerStatus::Ambiguous));
        Ok::<_, ReadyError>(if answered {
            Readiness::Ready(())
        } else {
            Readiness::Waiting("answer naming a partner for the latest gesture".to_owned())
        })
    })?;
    drop(client);
    on_line("ready\n").map_err(RunError::Output)?;
    // A node of its own hears SIGINT and SIGTERM (iceoryx2's handling).
    let node = create_node(&config.ipc, &format!("vref-up-wait-{pid}"))?;
    let end = options.duration.map(|d| Instant::now() + d);
    while nap(&node, CHECK_EVERY) {
        services
            .ensure_running()
            .map_err(|source| RunError::Died { run: "up", source })?;
        if end.is_some_and(|end| Instant::now() >= end) {
            break;
        }
    }
    Ok(())
}
