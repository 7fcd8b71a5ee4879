use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;

use super::error::{IpcError, iceoryx_err};
use super::{IpcSettings, Node, create_node, drain, open_decision, slice_publisher_qos};
use crate::{DecisionEntry, DecisionHeader, MAX_DECISION_PAIRS, SCHEMA_VERSION};

/// The matcher's side: publishes each finished solve's decision, written in
/// place into loaned shared memory, and wakes the viewers.
pub struct DecisionPublisher {
    publisher: Publisher<ipc::Service, [DecisionEntry], DecisionHeader>,
    notifier: Notifier<ipc::Service>,
}

impl std::fmt::Debug for DecisionPublisher {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DecisionPublisher").finish_non_exhaustive()
    }
}

impl DecisionPublisher {
    pub fn new(node: &Node, settings: &IpcSettings) -> Result<Self, IpcError> {
        let qos = slice_publisher_qos(settings);
        let (data, event) = open_decision(node, settings)?;
        let publisher = data
            .publisher_builder()
            .initial_max_slice_len(qos.initial_max_slice_len)
            .allocation_strategy(qos.allocation_strategy)
            .create()
            .map_err(|e| iceoryx_err("creating decision publisher", e))?;
        let notifier = event
            .notifier_builder()
            .create()
            .map_err(|e| iceoryx_err("creating decision notifier", e))?;
        Ok(Self {
            publisher,
            notifier,
        })
    }

    /// Publishes `header` with `count` entries, the i-th written by
    /// `entry(i)`; `pair_count` and the schema version are filled in.
    pub fn publish(
        &mut self,
        mut header: DecisionHeader,
        count: usize,
        entry: impl FnMut(usize) -> DecisionEntry,
    ) -> Result<(), IpcError> {
        if count > MAX_DECISION_PAIRS {
            return Err(IpcError::TooManyObjects {
                count,
                capacity: MAX_DECISION_PAIRS,
            });
        }
        header.pair_count = u32::try_from(count).unwrap_or(u32::MAX);
        header.schema_version = SCHEMA_VERSION;
        let mut sample = self
            .publisher
            .loan_slice_uninit(count)
            .map_err(|e| iceoryx_err("loaning a decision", e))?;
        *sample.user_header_mut() = header;
        sample
            .write_from_fn(entry)
            .send()
            .map_err(|e| iceoryx_err("sending a decision", e))?;
        self.notifier
            .notify()
            .map_err(|e| iceoryx_err("notifying a decision", e))?;
        Ok(())
    }
}

/// A decision as read back: the header and the entries it counts.
#[derive(Debug, Clone, PartialEq)]
pub struct Decision {
    pub header: DecisionHeader,
    pub entries: Vec<DecisionEntry>,
}

/// Why a decision read from shared memory was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DecisionError {
    #[error("decision schema version {found}, expected {expected}")]
    SchemaVersion { found: u32, expected: u32 },
    #[error("decision counts {count} pairs but carries {carried}")]
    PairCount { count: u32, carried: usize },
}

impl Decision {
    /// Copies a decision out of shared memory, checking what its header
    /// claims against what the sample carries.
    pub fn read(header: &DecisionHeader, entries: &[DecisionEntry]) -> Result<Self, DecisionError> {
        if header.schema_version != SCHEMA_VERSION {
            return Err(DecisionError::SchemaVersion {
                found: header.schema_version,
                expected: SCHEMA_VERSION,
            });
        }
        let count = header.pair_count as usize;
        if count > entries.len() || count > MAX_DECISION_PAIRS {
            return Err(DecisionError::PairCount {
                count: header.pair_count,
                carried: entries.len(),
            });
        }
        Ok(Self {
            header: *header,
            entries: entries[..count].to_vec(),
        })
    }

    /// The method's name as carried (up to the first zero byte).
    pub fn method(&self) -> String {
        let bytes = &self.header.method;
        let len = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
        String::from_utf8_lossy(&bytes[..len]).into_owned()
    }
}

/// Reads the matcher's latest decision; the matcher need not be running
/// yet, and a restarted matcher is picked up.
pub struct DecisionReader {
    // The port before the node: fields drop in order, the node last.
    subscriber: Subscriber<ipc::Service, [DecisionEntry], DecisionHeader>,
    _node: Node,
}

impl std::fmt::Debug for DecisionReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DecisionReader").finish_non_exhaustive()
    }
}

impl DecisionReader {
    /// Connects under the settings' namespace; `name` names this reader's
    /// node.
    pub fn connect(settings: &IpcSettings, name: &str) -> Result<Self, IpcError> {
        let node = create_node(settings, name)?;
        let (data, _event) = open_decision(&node, settings)?;
        let subscriber = data
            .subscriber_builder()
            .create()
            .map_err(|e| iceoryx_err("creating decision subscriber", e))?;
        Ok(Self {
            subscriber,
            _node: node,
        })
    }

    /// The newest decision published since the last call, if any; a
    /// malformed one is an error and is skipped.
    pub fn latest(&self) -> Result<Option<Result<Decision, DecisionError>>, IpcError> {
        let newest = drain::newest(&self.subscriber)
            .into_result()
            .map_err(|e| iceoryx_err("receiving a decision", e))?;
        Ok(newest.map(|sample| Decision::read(sample.user_header(), sample.payload())))
    }
}
