//! The harness that runs the whole system for a measurement, apart from
//! the `vref` command line that parses arguments and prints:
//!
//! - [`launch`]: the one process launcher. Service binaries under an
//!   iceoryx2 root path and prefix of their own, each logging to a file;
//!   stopped with SIGTERM, killed after a bound.
//! - [`ready`]: the one readiness wait, bounded by a timeout.
//! - [`netns`]: the loopback-only network namespace DDS runs in.
//! - [`echo`]: the echo server of `vref bench query` (the bare iceoryx2
//!   round trip).
//! - [`demo`], [`soak`], [`bench_query`], [`bench_remote`],
//!   [`bench_client`]: the runners of `vref demo`, `vref soak` and `vref
//!   bench query`, `remote` and `client`, each returning a report that
//!   renders itself as the command's JSON line or table.
//! - [`up`]: the runner of `vref up`, the services for clients to talk
//!   to until asked to stop.
//! - [`table`]: the plain-text tables the reports render.
//! - [`samples`]: round trips of one kind, with vref_measure's one
//!   percentile definition (nearest rank).
//!
//! Nothing here prints or exits; errors are one thiserror enum per concern
//! ([`launch::LaunchError`], [`ready::ReadyError`], [`echo::EchoError`],
//! [`RunError`] for the runners).

pub mod bench_client;
pub mod bench_query;
pub mod bench_remote;
pub mod demo;
pub mod echo;
pub mod launch;
pub mod netns;
pub mod ready;
pub mod samples;
pub mod soak;
pub mod table;
pub mod up;

use vref_wire::ipc::IpcError;

/// Why a runner (demo, soak, query benchmark) did not give a report.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// A feed's setup (a world, a data set): the caller's input.
    #[error(transparent)]
    Setup(#[from] vref_feed::SetupError),
    /// `vref demo --source` names neither the synthetic world nor a BOP
    /// folder.
    #[error("--source {0}: the demo runs on synthetic or bop:DIR")]
    DemoSource(String),
    /// `vref bench query --objects` below two.
    #[error("--objects: at least 2")]
    TooFewObjects,
    #[error(transparent)]
    Launch(#[from] launch::LaunchError),
    #[error(transparent)]
    Ready(#[from] ready::ReadyError),
    #[error(transparent)]
    Ipc(#[from] IpcError),
    /// A service died while the run measured.
    #[error("a service died during the {run}")]
    Died {
        run: &'static str,
        source: launch::LaunchError,
    },
    /// The matcher published no statistics in time.
    #[error("the matcher published no statistics within {0:?}")]
    NoStats(std::time::Duration),
    /// No matcher answered as the run needs (`vref bench client`).
    #[error("no answer as the run needs (is the matcher running with both feeds?)")]
    NotServing(#[source] Box<ready::ReadyError>),
    /// `vref bench remote`: the Zenoh echo did not start.
    #[error("starting the Zenoh echo")]
    Echo(#[source] vref_bridge::NetError),
    /// `vref bench remote`: no loopback port to listen on.
    #[error("finding a free loopback port")]
    FreePort(#[source] std::io::Error),
    /// `vref bench remote`: no session with the bridge or the echo.
    #[error("connecting to the {what} at {endpoint} (last error: {last})")]
    Connect {
        what: String,
        endpoint: String,
        last: String,
        #[source]
        source: Box<ready::ReadyError>,
    },
    /// The caller's output callback failed (e.g. stdout closed).
    #[error("writing the run's output")]
    Output(#[source] OutputError),
}

/// Why the caller's output callback failed.
pub type OutputError = Box<dyn std::error::Error + Send + Sync>;

impl vref_logging::exit::Fault for RunError {
    /// The caller asked wrong (a feed's setup, the demo's source, too few
    /// objects), rather than the run broke.
    fn is_bad_input(&self) -> bool {
        matches!(
            self,
            RunError::Setup(_) | RunError::DemoSource(_) | RunError::TooFewObjects
        )
    }
}

/// A run's report and how its services stopped (a report can be complete
/// though a service then failed to stop cleanly).
#[derive(Debug)]
pub struct Finished<R> {
    pub report: R,
    pub stopped: Result<(), crate::launch::LaunchError>,
}

/// Seconds since the Unix epoch (the feeds' clock).
pub fn now_s() -> f64 {
    vref_wire::ipc::now_ns() as f64 / 1e9
}
