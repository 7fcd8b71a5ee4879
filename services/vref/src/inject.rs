//! `vref inject`: a hostile publisher. Writes one kind of malformed
//! message (crate vref-inject builds them) into the running services, so
//! that their refusal can be seen from outside.

use std::path::PathBuf;
use std::time::Duration;

use clap::{Args, ValueEnum};
use vref_config::Config;
use vref_inject::{Kind, Message, Target};
use vref_logging::exit::{Blame, Failure};
use vref_scene::Side;
use vref_wire::ipc::{
    GesturePublisher, SnapshotPublisher, create_node, drain, now_ns, open_gesture, open_snapshot,
};

/// How long the publisher stays after its last message, and between the
/// messages of kinds that must be taken one at a time. A subscriber opens
/// a publisher's memory on its next receive: a publisher that left at
/// once could take an unread sample with it.
const SETTLE: Duration = Duration::from_millis(500);

#[derive(Debug, Args)]
pub struct InjectArgs {
    /// What to publish (valid, nan, inf, huge, count-over-slice,
    /// count-over-capacity, feature-dim-too-large, feature-dim-other-side,
    /// duplicate-ids, zero-ray, schema-version, sequence-backwards,
    /// future-stamp, old-stamp, hijack-sequence, hijack-ray: these two
    /// take the live feed's session with sequence 2^64-1; bad-up: an up
    /// vector flagged as known but zero).
    #[arg(long, value_name = "K", value_parser = parse_kind)]
    pub kind: Kind,
    /// Which view's snapshot service to write to (rays ignore it).
    #[arg(long, value_enum, default_value_t = SideArg::Robot)]
    pub side: SideArg,
    /// Rounds to publish; sequences move forward from round to round.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub count: u64,
    /// Configuration file (its [ipc] says where the services are, its
    /// [scene] capacity what `count-over-capacity` exceeds).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SideArg {
    Robot,
    Human,
}

fn parse_kind(s: &str) -> Result<Kind, String> {
    s.parse()
        .map_err(|e: vref_inject::UnknownKind| e.to_string())
}

pub fn run(args: &InjectArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    let side = match args.side {
        SideArg::Robot => Side::Robot,
        SideArg::Human => Side::Human,
    };
    let ipc = &config.ipc;
    let node = create_node(ipc, &format!("vref-inject-{}", std::process::id())).runtime()?;
    let session = if args.kind.hijacks() {
        live_session(&node, ipc, side, args.kind.is_ray()).runtime()?
    } else {
        session()
    };
    let target = Target {
        side,
        session,
        capacity: config.scene.capacity,
        timestamp_ns: now_ns(),
    };
    // Only the port the kind writes to: a spare publisher would take a
    // place a real feed may need.
    let mut publisher = if args.kind.is_ray() {
        Publisher::Rays(GesturePublisher::new(&node, ipc).runtime()?)
    } else {
        Publisher::Snapshots(SnapshotPublisher::new(&node, ipc, side, "").runtime()?)
    };
    for round in 0..args.count {
        for message in vref_inject::messages(args.kind, &target, round) {
            let line = publisher.publish(&message).runtime()?;
            crate::stdout::print(&format!(
                "{} {side}: {line}, session {}\n",
                args.kind, target.session
            ))?;
            if args.kind.needs_settling() {
                std::thread::sleep(SETTLE);
            }
        }
    }
    if !args.kind.needs_settling() {
        std::thread::sleep(SETTLE);
    }
    Ok(())
}

enum Publisher {
    Snapshots(SnapshotPublisher),
    Rays(GesturePublisher),
}

impl Publisher {
    /// Publishes `message` exactly as built; says what went out.
    fn publish(&mut self, message: &Message) -> anyhow::Result<String> {
        match (self, message) {
            (Publisher::Snapshots(p), Message::Snapshot { header, entries }) => {
                p.publish_raw(*header, entries)?;
                Ok(format!("snapshot sequence {}", header.sequence))
            }
            (Publisher::Rays(p), Message::Ray(ray)) => {
                p.publish_raw(*ray)?;
                Ok(format!("ray sequence {}", ray.sequence))
            }
            _ => Err(anyhow::anyhow!("no publisher for this message")),
        }
    }
}

/// How long a hijack waits for the live feed's latest message.
const LIVE_WITHIN: Duration = Duration::from_secs(5);

/// The session of the feed publishing on `side`'s snapshot service (or the
/// gesture service): any subscriber can read it.
fn live_session(
    node: &vref_wire::ipc::Node,
    ipc: &vref_wire::ipc::IpcSettings,
    side: Side,
    rays: bool,
) -> anyhow::Result<u64> {
    let deadline = std::time::Instant::now() + LIVE_WITHIN;
    let gone = || anyhow::anyhow!("no feed published within {LIVE_WITHIN:?}: nothing to hijack");
    if rays {
        let (data, _) = open_gesture(node, ipc)?;
        let sub = data
            .subscriber_builder()
            .create()
            .map_err(|e| anyhow::anyhow!("subscribing to rays: {e:?}"))?;
        while std::time::Instant::now() < deadline {
            if let Some(sample) = newest(&sub)? {
                return Ok(sample.payload().session);
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        return Err(gone());
    }
    let (data, _) = open_snapshot(node, ipc, side)?;
    let sub = data
        .subscriber_builder()
        .create()
        .map_err(|e| anyhow::anyhow!("subscribing to snapshots: {e:?}"))?;
    while std::time::Instant::now() < deadline {
        if let Some(sample) = newest(&sub)? {
            return Ok(sample.user_header().session);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    Err(gone())
}

/// The newest sample waiting: the live feed's session, even when an older
/// one's sample is still queued.
fn newest<R: drain::Receive>(sub: &R) -> anyhow::Result<Option<R::Sample>> {
    drain::newest(sub)
        .into_result()
        .map_err(|e| anyhow::anyhow!("{e:?}"))
}

/// A session id of this run: the start time mixed with the process id, so
/// that two runs never share one.
fn session() -> u64 {
    now_ns().rotate_left(17) ^ u64::from(std::process::id())
}
