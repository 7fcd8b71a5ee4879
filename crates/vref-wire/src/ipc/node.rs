use std::os::unix::ffi::OsStrExt;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use iceoryx2::node::NodeWaitFailure;
use iceoryx2::waitset::WaitSetRunResult;

use iceoryx2::prelude::*;

use super::IpcSettings;
use super::error::{IpcError, iceoryx_err};

/// The node type of every vref process.
pub type Node = iceoryx2::node::Node<ipc::Service>;

/// Creates a node named `name` in the settings' root path and prefix.
/// Termination requests (SIGINT, SIGTERM) make `node.wait` fail, which
/// the services take as the signal to stop cleanly.
pub fn create_node(settings: &IpcSettings, name: &str) -> Result<Node, IpcError> {
    let mut config = base_config(settings)?;
    if let Some(root) = &settings.root_path {
        let mut bytes = root.as_os_str().as_bytes().to_vec();
        if !bytes.ends_with(b"/") {
            bytes.push(b'/');
        }
        let path = Path::new(&bytes).map_err(|_| IpcError::BadName {
            what: "ipc.root_path",
            value: root.display().to_string(),
        })?;
        config.global.set_root_path(&path);
    }
    config.global.prefix =
        FileName::new(settings.prefix.as_bytes()).map_err(|_| IpcError::BadName {
            what: "ipc.prefix",
            value: settings.prefix.clone(),
        })?;
    let node_name = NodeName::new(name).map_err(|_| IpcError::BadName {
        what: "node name",
        value: name.to_owned(),
    })?;
    NodeBuilder::new()
        .name(&node_name)
        .config(&config)
        .signal_handling_mode(SignalHandlingMode::HandleTerminationRequests)
        .create::<ipc::Service>()
        .map_err(|e| iceoryx_err(format!("creating node {name}"), e))
}

/// Sleeps up to `cycle` on the node; `false` once a termination request
/// (SIGINT, SIGTERM) arrived. Other signals (SIGCONT after SIGSTOP,
/// SIGCHLD, SIGWINCH) cut the sleep short without asking anything, and a
/// service must keep running through them: iceoryx2 reports both as
/// failures of `wait`, and only the termination request is sticky.
pub fn nap(node: &Node, cycle: Duration) -> bool {
    match node.wait(cycle) {
        Ok(()) => true,
        Err(NodeWaitFailure::TerminationRequest) => false,
        Err(NodeWaitFailure::Interrupt) => !matches!(
            node.wait(Duration::ZERO),
            Err(NodeWaitFailure::TerminationRequest)
        ),
    }
}

/// The shortest timeout a listener's `timed_wait` honours. iceoryx2 0.10
/// waits on a socket receive timeout in whole microseconds, and one that
/// rounds to zero is no timeout: the wait blocks until a notification
/// comes, for ever if none does (a client whose deadline was under a
/// microsecond away hung that way in CI). Every listener wait goes
/// through [`listener_timeout`].
pub const SHORTEST_LISTENER_WAIT: Duration = Duration::from_micros(1);

/// `wait`, at least [`SHORTEST_LISTENER_WAIT`].
pub fn listener_timeout(wait: Duration) -> Duration {
    wait.max(SHORTEST_LISTENER_WAIT)
}

/// Whether a WaitSet's run ended because the process was asked to stop.
/// `Interrupt` is any signal that cut the wait short: a SIGINT is
/// reported as `TerminationRequest` on the next run, so only that one
/// stops.
pub fn termination_requested(result: &WaitSetRunResult) -> bool {
    matches!(result, WaitSetRunResult::TerminationRequest)
}

/// iceoryx2's configuration before vref's `[ipc]` overrides: the named
/// file, or what iceoryx2 finds by itself.
fn base_config(settings: &IpcSettings) -> Result<Config, IpcError> {
    let Some(file) = &settings.iceoryx2_config else {
        return Ok(Config::global_config().clone());
    };
    let bad = || IpcError::BadName {
        what: "ipc.iceoryx2_config",
        value: file.display().to_string(),
    };
    let path = FilePath::new(file.as_os_str().as_bytes()).map_err(|_| bad())?;
    Config::from_file(&path).map_err(|e| iceoryx_err(format!("reading {}", file.display()), e))
}

/// Wall-clock time in nanoseconds since the Unix epoch: the timestamps of
/// snapshots and rays, comparable across processes.
pub fn now_ns() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX))
}
