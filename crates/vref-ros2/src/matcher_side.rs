//! The matcher's side of what vref-ros2 relays: the human view the
//! matcher matches against and its decisions, each kept to the newest.
//! The bridge and the recorder read them alike.

use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use vref_scene::Side;
use vref_view::View;
use vref_wire::ipc::{Decision, IpcError, IpcSettings, Node, drain, open_decision, open_snapshot};
use vref_wire::{DecisionEntry, DecisionHeader, ObjectEntry, SnapshotHeader};

/// The human view's and the decisions' subscribers, and the newest of
/// each taken so far.
pub(crate) struct MatcherSide {
    human: Subscriber<ipc::Service, [ObjectEntry], SnapshotHeader>,
    decisions: Subscriber<ipc::Service, [DecisionEntry], DecisionHeader>,
    pub(crate) human_view: Option<View>,
    pub(crate) decision: Option<Decision>,
}

/// What one [`MatcherSide::take`] brought.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct News {
    pub(crate) view: bool,
    pub(crate) decision: bool,
}

impl MatcherSide {
    pub(crate) fn open(node: &Node, ipc: &IpcSettings) -> Result<Self, IpcError> {
        let iox = |what: &str| {
            let what = format!("creating {what} subscriber");
            move |e: &dyn std::fmt::Debug| IpcError::Iceoryx {
                what,
                message: format!("{e:?}"),
            }
        };
        let (human_port, _) = open_snapshot(node, ipc, Side::Human)?;
        let human = human_port
            .subscriber_builder()
            .create()
            .map_err(|e| iox("human snapshot")(&e))?;
        let (decision_port, _) = open_decision(node, ipc)?;
        let decisions = decision_port
            .subscriber_builder()
            .create()
            .map_err(|e| iox("decision")(&e))?;
        Ok(Self {
            human,
            decisions,
            human_view: None,
            decision: None,
        })
    }

    /// Takes every sample waiting, keeping the newest view and decision;
    /// a decision that does not read is logged and skipped, and so is a
    /// failed receive (the next turn tries again).
    pub(crate) fn take(&mut self) -> News {
        let mut news = News::default();
        let drained = drain::newest(&self.human);
        if let Some(e) = &drained.error {
            tracing::warn!("receiving a human snapshot: {e:?}");
        }
        if let Some(sample) = drained.newest {
            self.human_view = Some(View::from_wire(sample.user_header(), sample.payload()));
            news.view = true;
        }
        let taken = drain::each(&self.decisions, |sample| {
            match Decision::read(sample.user_header(), sample.payload()) {
                Ok(d) => {
                    self.decision = Some(d);
                    news.decision = true;
                }
                Err(e) => tracing::warn!("decision refused: {e}"),
            }
        });
        if let Err(e) = taken {
            tracing::warn!("receiving a decision: {e:?}");
        }
        news
    }
}
