//! A dataset file as a feed: one view of each scene pair in turn, each
//! held for a while, repeated at the snapshot rate. The pair shown is a
//! function of the time since the epoch, so the two feeds show the same
//! pair without talking.

use std::path::Path;

use vref_scene::{Limits, ScenePair, Side, read_dataset_file};
use vref_wire::{ObjectEntry, wire_up};

use crate::entries::graph_entries;
use crate::ticks::Ticker;
use crate::{Due, Publication, SetupError};

/// One view of a pair, as published.
#[derive(Debug)]
pub(crate) struct View {
    pub(crate) feature_dim: usize,
    pub(crate) entries: Vec<ObjectEntry>,
    pub(crate) up: Option<[f32; 3]>,
}

#[derive(Debug)]
pub(crate) struct DatasetSource {
    /// Per pair: this feed's view.
    views: Vec<View>,
    hold_s: f64,
    snapshots: Ticker,
}

impl DatasetSource {
    pub(crate) fn load(
        path: &Path,
        side: Side,
        limits: Limits,
        hold_s: f64,
        epoch_ns: u64,
        rate_hz: f64,
    ) -> Result<Self, SetupError> {
        let pairs = read_dataset_file(path, limits).map_err(|source| SetupError::Dataset {
            path: path.to_owned(),
            source,
        })?;
        if pairs.is_empty() {
            return Err(SetupError::EmptyDataset {
                path: path.to_owned(),
            });
        }
        let origin = format!("dataset {}", path.display());
        Self::from_pairs(&origin, &pairs, side, hold_s, epoch_ns, rate_hz)
    }

    /// `pairs` (not empty) in turn; `origin` names them in errors.
    pub(crate) fn from_pairs(
        origin: &str,
        pairs: &[ScenePair],
        side: Side,
        hold_s: f64,
        epoch_ns: u64,
        rate_hz: f64,
    ) -> Result<Self, SetupError> {
        let views = pairs
            .iter()
            .map(|pair| {
                let graph = match side {
                    Side::Robot => &pair.robot,
                    Side::Human => &pair.human,
                };
                graph_entries(graph)
                    .map(|entries| View {
                        feature_dim: graph.feature_dim(),
                        entries,
                        up: wire_up(graph),
                    })
                    .map_err(|source| SetupError::Entry {
                        origin: format!("{origin}, scene {:?}", pair.name),
                        source,
                    })
            })
            .collect::<Result<_, _>>()?;
        Ok(Self::from_views(views, hold_s, epoch_ns, rate_hz))
    }

    /// `views` in turn, each for `hold_s`.
    pub(crate) fn from_views(views: Vec<View>, hold_s: f64, epoch_ns: u64, rate_hz: f64) -> Self {
        Self {
            views,
            hold_s,
            snapshots: Ticker::new(epoch_ns, rate_hz),
        }
    }

    pub(crate) fn pairs(&self) -> usize {
        self.views.len()
    }

    /// When the next snapshot is due.
    pub(crate) fn peek_at(&self, now_ns: u64) -> u64 {
        self.snapshots.peek(now_ns).at_ns
    }

    pub(crate) fn next(&mut self, now_ns: u64) -> Due<'_> {
        let tick = self.snapshots.peek(now_ns);
        self.snapshots.take(tick);
        let slot = (tick.t / self.hold_s).floor() as i64;
        let count = i64::try_from(self.views.len()).unwrap_or(i64::MAX).max(1);
        let index = usize::try_from(slot.rem_euclid(count)).unwrap_or(0);
        let publication = match self.views.get(index) {
            Some(view) => Publication::Snapshot {
                feature_dim: view.feature_dim,
                entries: &view.entries,
                up: view.up,
            },
            None => Publication::Snapshot {
                feature_dim: 0,
                entries: &[],
                up: None,
            },
        };
        Due {
            at_ns: tick.at_ns,
            publication,
        }
    }
}
