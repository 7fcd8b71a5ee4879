//! A recording as a feed: this feed's frames, with their original spacing,
//! over and over. Either format (MCAP or vref's own) is read whole, or up
//! to where it was cut short (a recorder killed): what is complete is
//! replayed, and where it stopped is said.

use std::path::Path;

use vref_record::{Cut, Frame, RecordedSnapshot, read_recording};
use vref_scene::Side;
use vref_wire::ObjectEntry;

use crate::entries::{check_dim, entry};
use crate::{Due, EntryError, Publication, Ray, SetupError};

/// A replay this late re-anchors instead of catching up in a burst.
const MAX_LATE_NS: u64 = 1_000_000_000;

#[derive(Debug)]
pub(crate) struct Replay {
    /// Offset from the first frame, and what to publish.
    items: Vec<(u64, Item)>,
    /// One pass: the last frame's offset plus a mean gap.
    span_ns: u64,
    /// When the current pass started.
    anchor_ns: Option<u64>,
    next: usize,
    cut: Option<Cut>,
}

#[derive(Debug)]
enum Item {
    Snapshot {
        feature_dim: usize,
        entries: Vec<ObjectEntry>,
        up: Option<[f32; 3]>,
    },
    Gesture(Ray),
}

impl Replay {
    /// Reads this feed's frames: `side`'s snapshots, and rays if
    /// `gestures`. A single frame repeats every `fallback_gap_ns`.
    pub(crate) fn load(
        path: &Path,
        side: Side,
        gestures: bool,
        fallback_gap_ns: u64,
    ) -> Result<Self, SetupError> {
        let bytes = std::fs::read(path).map_err(|source| SetupError::OpenRecording {
            path: path.to_owned(),
            source,
        })?;
        let recorded = read_recording(&bytes).map_err(|source| SetupError::Recording {
            path: path.to_owned(),
            source,
        })?;
        if let Some(cut) = &recorded.cut {
            tracing::warn!(path = %path.display(), "{cut}; replaying what is complete");
        }
        let mut frames: Vec<(u64, Item)> = Vec::new();
        for (index, frame) in recorded.frames.into_iter().enumerate() {
            let item = match frame {
                Frame::Snapshot(s) if s.side() == side => {
                    let item = snapshot_item(&s).map_err(|source| SetupError::Entry {
                        origin: format!("recording {}, frame {index}", path.display()),
                        source,
                    })?;
                    (s.timestamp_ns, item)
                }
                Frame::Gesture(r) if gestures => (
                    r.timestamp_ns,
                    Item::Gesture(Ray {
                        origin: r.origin,
                        direction: r.direction,
                        cone_half_angle: r.cone_half_angle,
                        confidence: r.confidence,
                    }),
                ),
                _ => continue,
            };
            frames.push(item);
        }
        if frames.is_empty() {
            return Err(SetupError::EmptyRecording {
                path: path.to_owned(),
                cut: recorded.cut,
                what: match (side, gestures) {
                    (Side::Robot, _) => "robot snapshots",
                    (Side::Human, false) => "human snapshots",
                    (Side::Human, true) => "human snapshots or pointing rays",
                },
            });
        }
        Ok(Self::from_items(frames, recorded.cut, fallback_gap_ns))
    }

    /// Snapshots measured elsewhere (a rosbag2 file's frames), each at its
    /// own stamp, with the up vector its measurement found.
    pub(crate) fn from_snapshots(snapshots: Vec<crate::BagSnapshot>, fallback_gap_ns: u64) -> Self {
        let items = snapshots
            .into_iter()
            .map(|s| {
                (
                    s.stamp_ns,
                    Item::Snapshot {
                        feature_dim: vref_perception::FEATURE_DIM,
                        entries: s.entries,
                        up: s.up,
                    },
                )
            })
            .collect();
        Self::from_items(items, None, fallback_gap_ns)
    }

    fn from_items(mut frames: Vec<(u64, Item)>, cut: Option<Cut>, fallback_gap_ns: u64) -> Self {
        // Feeds of a recording were separate processes: their frames are
        // in arrival order, not strictly by timestamp.
        frames.sort_by_key(|(ts, _)| *ts);
        let first = frames.first().map_or(0, |(ts, _)| *ts);
        let items: Vec<(u64, Item)> = frames
            .into_iter()
            .map(|(ts, item)| (ts.saturating_sub(first), item))
            .collect();
        let last = items.last().map_or(0, |(offset, _)| *offset);
        let gaps = (items.len() as u64).saturating_sub(1);
        let mean_gap = if gaps > 0 && last > 0 {
            last / gaps
        } else {
            fallback_gap_ns
        };
        Self {
            items,
            span_ns: last + mean_gap.max(1),
            anchor_ns: None,
            next: 0,
            cut,
        }
    }

    /// Where the file was cut short, if it was.
    pub(crate) fn cut(&self) -> Option<&Cut> {
        self.cut.as_ref()
    }

    pub(crate) fn frames(&self) -> usize {
        self.items.len()
    }

    /// Seconds of one pass.
    pub(crate) fn span_s(&self) -> f64 {
        self.span_ns as f64 / 1e9
    }

    pub(crate) fn next(&mut self, now_ns: u64) -> Due<'_> {
        if self.next >= self.items.len() {
            self.next = 0;
            self.anchor_ns = self.anchor_ns.map(|a| a.saturating_add(self.span_ns));
        }
        let index = self.next;
        self.next += 1;
        let offset = self.items.get(index).map_or(0, |(offset, _)| *offset);
        let mut anchor = *self.anchor_ns.get_or_insert(now_ns);
        if anchor.saturating_add(offset).saturating_add(MAX_LATE_NS) < now_ns {
            anchor = now_ns.saturating_sub(offset);
            self.anchor_ns = Some(anchor);
        }
        let publication = match self.items.get(index).map(|(_, item)| item) {
            Some(Item::Snapshot {
                feature_dim,
                entries,
                up,
            }) => Publication::Snapshot {
                feature_dim: *feature_dim,
                entries,
                up: *up,
            },
            Some(Item::Gesture(ray)) => Publication::Gesture {
                ray: *ray,
                target: None,
            },
            None => Publication::Snapshot {
                feature_dim: 0,
                entries: &[],
                up: None,
            },
        };
        Due {
            at_ns: anchor.saturating_add(offset),
            publication,
        }
    }
}

/// A recorded snapshot as it was sent, faults and all, as long as the
/// wire can carry it.
fn snapshot_item(s: &RecordedSnapshot) -> Result<Item, EntryError> {
    let feature_dim = check_dim(s.feature_dim as usize)?;
    let entries = s
        .objects
        .iter()
        .map(|o| {
            entry(
                o.track_id,
                o.position.map(f64::from),
                o.position_sigma.map(f64::from),
                &o.feature,
            )
        })
        .collect::<Result<_, _>>()?;
    Ok(Item::Snapshot {
        feature_dim,
        entries,
        // As recorded, unchecked like the rest: a replay reproduces a bad
        // up vector too.
        up: s.up,
    })
}
