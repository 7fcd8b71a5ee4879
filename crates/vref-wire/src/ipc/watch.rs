use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use vref_scene::Side;

use super::error::{IpcError, iceoryx_err};
use super::{IpcSettings, Node, create_node, drain, open_snapshot};
use crate::{ObjectEntry, SnapshotHeader};

/// Watches one side's snapshots without reading their objects: for tools
/// that must know a feed is publishing before they go on (the benchmarks
/// wait on it instead of sleeping a guess).
pub struct SnapshotWatch {
    // The port before the node: fields drop in order, the node last.
    subscriber: Subscriber<ipc::Service, [ObjectEntry], SnapshotHeader>,
    _node: Node,
}

impl std::fmt::Debug for SnapshotWatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SnapshotWatch").finish_non_exhaustive()
    }
}

impl SnapshotWatch {
    /// Connects to `side`'s snapshots under the settings' namespace; the
    /// feed need not be running yet. `name` names this watch's node.
    pub fn connect(settings: &IpcSettings, side: Side, name: &str) -> Result<Self, IpcError> {
        let node = create_node(settings, name)?;
        let (data, _event) = open_snapshot(&node, settings, side)?;
        let subscriber = data
            .subscriber_builder()
            .create()
            .map_err(|e| iceoryx_err("creating a snapshot subscriber", e))?;
        Ok(Self {
            subscriber,
            _node: node,
        })
    }

    /// The header of the newest snapshot that arrived since the last call
    /// (or the one kept for a late subscriber), if any.
    pub fn latest(&self) -> Result<Option<SnapshotHeader>, IpcError> {
        let newest = drain::newest(&self.subscriber)
            .into_result()
            .map_err(|e| iceoryx_err("receiving a snapshot", e))?;
        Ok(newest.map(|sample| *sample.user_header()))
    }
}
