//! A feed from its command line and configuration to its publications.

use std::path::Path;
use std::time::Duration;

use vref_config::Config;
use vref_scene::Side;
use vref_wire::ObjectEntry;

use vref_wire::ipc::{
    GesturePublisher, IpcSettings, Node, SnapshotPublisher, create_node, nap, now_ns,
};

use crate::args::{FeedArgs, SourceSpec};
use crate::bop::{BopSource, BopWorld};
use crate::dataset::DatasetSource;
use crate::entries::check_dim;
use crate::replay::Replay;
use crate::synthetic::{Synthetic, synthetic_world};
use crate::{Due, Publication, Role, RunError, SetupError, Target};

/// Longest single sleep: a paused feed still notices a signal this soon.
const MAX_NAP: Duration = Duration::from_millis(200);

/// A feed ready to run.
#[derive(Debug)]
pub struct Feed {
    role: Role,
    ipc: IpcSettings,
    source: Source,
    description: String,
    rate_hz: f64,
    gesture_rate_hz: Option<f64>,
}

#[derive(Debug)]
enum Source {
    // Boxed: a live world is large, and a feed holds one source for good.
    Synthetic(Box<Synthetic>),
    Dataset(DatasetSource),
    Bop(Box<BopSource>),
    Replay(Replay),
}

/// Reads the sources this crate cannot read itself: rosbag2 files, which
/// vref-ros2 decodes (it depends on this crate, so the feed binaries hand
/// its reader to [`Feed::prepare_with`]).
pub trait BagReader {
    /// `side`'s measured frames of the bag at `path`, each at its stamp
    /// (nanoseconds, the bag's clock; any order), and what was read, in
    /// words.
    fn read(
        &self,
        path: &Path,
        side: Side,
        config: &Config,
    ) -> Result<MeasuredBag, Box<dyn std::error::Error + Send + Sync>>;
}

/// A bag's frames, measured.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredBag {
    pub frames: Vec<BagSnapshot>,
    pub description: String,
}

/// One measured frame of a bag.
#[derive(Debug, Clone, PartialEq)]
pub struct BagSnapshot {
    /// Nanoseconds, the bag's clock.
    pub stamp_ns: u64,
    pub entries: Vec<ObjectEntry>,
    /// The camera's up vector, where the frame's measurement knew it.
    pub up: Option<[f32; 3]>,
}

/// What a feed published before it stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Published {
    pub snapshots: u64,
    pub gestures: u64,
}

impl Feed {
    /// Checks the options and the configuration and loads the source; no
    /// shared memory is touched yet. A rosbag source needs
    /// [`Feed::prepare_with`].
    pub fn prepare(role: Role, args: &FeedArgs, config: &Config) -> Result<Self, SetupError> {
        Self::prepare_with(role, args, config, None)
    }

    /// [`Feed::prepare`], with a reader for rosbag sources.
    pub fn prepare_with(
        role: Role,
        args: &FeedArgs,
        config: &Config,
        bags: Option<&dyn BagReader>,
    ) -> Result<Self, SetupError> {
        let feeds = &config.feeds;
        let rate_hz = positive(
            if args.rate.is_some() {
                "--rate"
            } else {
                "[feeds] snapshot_rate_hz"
            },
            args.rate.unwrap_or(feeds.snapshot_rate_hz),
        )?;
        let gesture_rate_hz = if role.points() {
            Some(positive("[feeds] gesture_rate_hz", feeds.gesture_rate_hz)?)
        } else {
            None
        };
        if args.world_up.is_some() && !matches!(args.source, SourceSpec::Bop(_)) {
            return Err(SetupError::WorldUpWithoutBop(args.source.to_string()));
        }
        let side = role.side();
        let (source, description) = match &args.source {
            SourceSpec::Synthetic => {
                let (preset, world) = synthetic_world(feeds, args.objects)?;
                check_dim(world.config().features.dim()).map_err(|source| SetupError::Entry {
                    origin: format!("preset {preset}"),
                    source,
                })?;
                let description = format!(
                    "synthetic world (preset {preset}, seed {}, {} objects, epoch {} ns)",
                    feeds.seed,
                    world.object_count(),
                    args.epoch_ns
                );
                let synthetic =
                    Synthetic::new(world, side, args.epoch_ns, rate_hz, gesture_rate_hz)
                        .with_up_vectors(feeds.up_vectors);
                (Source::Synthetic(Box::new(synthetic)), description)
            }
            SourceSpec::Dataset(path) => {
                let hold_s = positive(args.hold_flag(), args.hold_seconds())?;
                let limits = config.scene.limits();
                let dataset =
                    DatasetSource::load(path, side, limits, hold_s, args.epoch_ns, rate_hz)?;
                let description = format!(
                    "dataset {} ({} scene pairs, {hold_s} s each)",
                    path.display(),
                    dataset.pairs()
                );
                (Source::Dataset(dataset), description)
            }
            SourceSpec::Bop(path) => {
                let hold_s = positive(args.hold_flag(), args.hold_seconds())?;
                let world = BopWorld::load(
                    path,
                    args.world_up,
                    config.perception,
                    config.scene.limits(),
                    hold_s,
                )?;
                let bop = BopSource::new(world, side, args.epoch_ns, rate_hz, gesture_rate_hz)?;
                let description = format!(
                    "BOP {} ({} scenes, {hold_s} s each)",
                    path.display(),
                    bop.scenes()
                );
                (Source::Bop(Box::new(bop)), description)
            }
            SourceSpec::Rgbd(path) => {
                let hold_s = positive(args.hold_flag(), args.hold_seconds())?;
                let noise = args.noise.unwrap_or_default();
                let (views, summary) = crate::rgbd::load_views(
                    path,
                    side,
                    config.perception,
                    config.segmentation,
                    noise,
                )?;
                let description = format!(
                    "RGB-D frames {} ({} frames, {} with their own masks, {} without a supporting plane, {} objects; {hold_s} s each)",
                    path.display(),
                    summary.frames,
                    summary.with_masks,
                    summary.no_support,
                    summary.objects
                );
                let source = DatasetSource::from_views(views, hold_s, args.epoch_ns, rate_hz);
                (Source::Dataset(source), description)
            }
            SourceSpec::Rosbag(path) => {
                let reader = bags.ok_or_else(|| SetupError::NoBagReader { path: path.clone() })?;
                let mut config = config.clone();
                if let Some(noise) = args.noise {
                    config.ros2.depth_noise = noise;
                }
                let bag =
                    reader
                        .read(path, side, &config)
                        .map_err(|source| SetupError::Rosbag {
                            path: path.clone(),
                            source,
                        })?;
                let gap_ns = (1e9 / rate_hz).round() as u64;
                let replay = Replay::from_snapshots(bag.frames, gap_ns);
                let description = format!(
                    "rosbag {} ({}; {:.1} s per pass)",
                    path.display(),
                    bag.description,
                    replay.span_s()
                );
                (Source::Replay(replay), description)
            }
            SourceSpec::Recording(path) => {
                let gap_ns = (1e9 / rate_hz).round() as u64;
                let replay = Replay::load(path, side, role.points(), gap_ns)?;
                let mut description = format!(
                    "recording {} ({} frames, {:.1} s per pass)",
                    path.display(),
                    replay.frames(),
                    replay.span_s()
                );
                if let Some(cut) = replay.cut() {
                    description.push_str(&format!("; {cut}"));
                }
                (Source::Replay(replay), description)
            }
        };
        Ok(Self {
            role,
            ipc: config.ipc.clone(),
            source,
            description,
            rate_hz,
            gesture_rate_hz,
        })
    }

    pub fn role(&self) -> Role {
        self.role
    }

    /// Snapshots per second; `None` for a recording, which keeps its own
    /// timing.
    pub fn rate_hz(&self) -> Option<f64> {
        match self.source {
            Source::Replay(_) => None,
            _ => Some(self.rate_hz),
        }
    }

    /// Pointing rays per second, for a synthetic gesture feed.
    pub fn gesture_rate_hz(&self) -> Option<f64> {
        match self.source {
            Source::Synthetic(_) | Source::Bop(_) => self.gesture_rate_hz,
            _ => None,
        }
    }

    /// What is published, in words: the source, its file, its size.
    pub fn describe(&self) -> &str {
        &self.description
    }

    /// The IPC settings it publishes under.
    pub fn ipc(&self) -> &IpcSettings {
        &self.ipc
    }

    /// The next publication, as `run` would publish it if the clock read
    /// `now_ns` (Unix nanoseconds); for tests and tools that pace
    /// themselves.
    pub fn next(&mut self, now_ns: u64) -> Result<Due<'_>, RunError> {
        self.source.next(now_ns)
    }

    /// Publishes until SIGINT or SIGTERM. `on_target` hears of each new
    /// target the synthetic person points at. The ports and the node are
    /// released on return.
    pub fn run(&mut self, mut on_target: impl FnMut(&Target)) -> Result<Published, RunError> {
        let node = create_node(&self.ipc, self.role.node_name())?;
        // A predecessor killed without cleanup may still hold a port.
        node.try_cleanup_dead_nodes();
        // Declared after the node, so dropped before it.
        let mut snapshots =
            SnapshotPublisher::new(&node, &self.ipc, self.role.side(), self.role.frame_name())?;
        let mut gestures = if self.role.points() {
            Some(GesturePublisher::new(&node, &self.ipc)?)
        } else {
            None
        };
        let mut published = Published::default();
        let mut last_slot = None;
        loop {
            let due = self.source.next(now_ns())?;
            if !wait_until(&node, due.at_ns) {
                return Ok(published);
            }
            match due.publication {
                Publication::Snapshot {
                    feature_dim,
                    entries,
                    up,
                } => {
                    snapshots.publish(entries.len(), feature_dim, up, due.at_ns, |i| entries[i])?;
                    published.snapshots += 1;
                }
                Publication::Gesture { ray, target } => {
                    let Some(publisher) = &mut gestures else {
                        continue;
                    };
                    publisher.publish(
                        ray.origin,
                        ray.direction,
                        ray.cone_half_angle,
                        ray.confidence,
                    )?;
                    published.gestures += 1;
                    if let Some(target) = target
                        && last_slot != Some(target.slot)
                    {
                        last_slot = Some(target.slot);
                        on_target(&target);
                    }
                }
            }
        }
    }
}

impl Source {
    fn next(&mut self, now_ns: u64) -> Result<Due<'_>, RunError> {
        match self {
            Source::Synthetic(s) => s.next(now_ns),
            Source::Dataset(d) => Ok(d.next(now_ns)),
            Source::Bop(b) => Ok(b.next(now_ns)),
            Source::Replay(r) => Ok(r.next(now_ns)),
        }
    }
}

/// Sleeps until `at_ns` (Unix nanoseconds); `false` on SIGINT or SIGTERM.
/// Asks the node at least once even when already due, so that a feed
/// always behind still notices a signal.
fn wait_until(node: &Node, at_ns: u64) -> bool {
    let mut remaining = Duration::from_nanos(at_ns.saturating_sub(now_ns()));
    loop {
        if !nap(node, remaining.min(MAX_NAP)) {
            return false;
        }
        remaining = Duration::from_nanos(at_ns.saturating_sub(now_ns()));
        if remaining.is_zero() {
            return true;
        }
    }
}

fn positive(what: &'static str, value: f64) -> Result<f64, SetupError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(SetupError::BadNumber { what, value })
    }
}
