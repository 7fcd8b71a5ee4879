use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;

use super::error::{IpcError, iceoryx_err};
use super::{IpcSettings, Node, create_node, drain, open_stats};
use crate::MatcherStats;

/// The matcher's side: publishes its statistics.
pub struct StatsPublisher {
    publisher: Publisher<ipc::Service, MatcherStats, ()>,
}

impl std::fmt::Debug for StatsPublisher {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StatsPublisher").finish_non_exhaustive()
    }
}

impl StatsPublisher {
    pub fn new(node: &Node, settings: &IpcSettings) -> Result<Self, IpcError> {
        let publisher = open_stats(node, settings)?
            .publisher_builder()
            .create()
            .map_err(|e| iceoryx_err("creating stats publisher", e))?;
        Ok(Self { publisher })
    }

    pub fn publish(&self, stats: &MatcherStats) -> Result<(), IpcError> {
        self.publisher
            .loan_uninit()
            .map_err(|e| iceoryx_err("loaning stats", e))?
            .write_payload(*stats)
            .send()
            .map_err(|e| iceoryx_err("sending stats", e))?;
        Ok(())
    }
}

/// Reads the matcher's latest statistics; the matcher need not be running
/// yet, and a restarted matcher is picked up.
pub struct StatsReader {
    // The port before the node: fields drop in order, the node last.
    subscriber: Subscriber<ipc::Service, MatcherStats, ()>,
    _node: Node,
}

impl std::fmt::Debug for StatsReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StatsReader").finish_non_exhaustive()
    }
}

impl StatsReader {
    /// Connects under the settings' namespace; `name` names this reader's
    /// node.
    pub fn connect(settings: &IpcSettings, name: &str) -> Result<Self, IpcError> {
        let node = create_node(settings, name)?;
        let subscriber = open_stats(&node, settings)?
            .subscriber_builder()
            .create()
            .map_err(|e| iceoryx_err("creating stats subscriber", e))?;
        Ok(Self {
            subscriber,
            _node: node,
        })
    }

    /// The newest statistics published since the last call, if any.
    pub fn latest(&self) -> Result<Option<MatcherStats>, IpcError> {
        let newest = drain::newest(&self.subscriber)
            .into_result()
            .map_err(|e| iceoryx_err("receiving stats", e))?;
        Ok(newest.map(|sample| *sample.payload()))
    }
}
