//! What both feed binaries do between parsing their flags and choosing
//! their exit code.

use vref_config::{Config, ConfigError};
use vref_wire::ipc::ServiceNames;

use crate::{BagReader, Feed, FeedArgs, Published, Role, RunError, SetupError};

/// Why a feed could not start or stopped early.
#[derive(Debug, thiserror::Error)]
pub enum FeedError {
    #[error("configuration")]
    Config(#[source] ConfigError),
    #[error("feed setup")]
    Setup(#[source] SetupError),
    #[error("publishing")]
    Run(#[source] RunError),
}

impl vref_logging::exit::Fault for FeedError {
    /// The configuration, flags or source were wrong: everything but a
    /// failure while publishing.
    fn is_bad_input(&self) -> bool {
        !matches!(self, FeedError::Run(_))
    }
}

/// Loads the configuration, prepares the feed of `role`, logs what it
/// publishes and where, and publishes until SIGINT or SIGTERM.
pub fn run_feed(role: Role, args: &FeedArgs) -> Result<Published, FeedError> {
    run_feed_with(role, args, None)
}

/// [`run_feed`], with a reader for rosbag sources.
pub fn run_feed_with(
    role: Role,
    args: &FeedArgs,
    bags: Option<&dyn BagReader>,
) -> Result<Published, FeedError> {
    let (config, source) = Config::load(args.config.as_deref()).map_err(FeedError::Config)?;
    tracing::info!(?source, "configuration");
    let mut feed = Feed::prepare_with(role, args, &config, bags).map_err(FeedError::Setup)?;
    let ipc = feed.ipc();
    let names = ServiceNames::new(&ipc.namespace);
    tracing::info!(
        source = %feed.describe(),
        service = %names.snapshot(role.side()),
        gesture_service = ?role.points().then(|| names.gesture()),
        frame = role.frame_name(),
        root_path = ?ipc.root_path,
        prefix = %ipc.prefix,
        rate_hz = ?feed.rate_hz(),
        gesture_rate_hz = ?feed.gesture_rate_hz(),
        "{} publishing",
        role.node_name()
    );
    let published = feed
        .run(|target| {
            tracing::info!(
                slot = target.slot,
                human_object = target.human_id,
                robot_object = target.robot_id,
                "pointing at a new object"
            );
        })
        .map_err(FeedError::Run)?;
    tracing::info!(
        snapshots = published.snapshots,
        gestures = published.gestures,
        "{} stopped",
        role.node_name()
    );
    Ok(published)
}
