use std::fs::File;
use std::io::BufWriter;
use std::path::Path;
use std::time::{Duration, Instant};

use anyhow::{Context, anyhow};
use iceoryx2::prelude::*;
use vref_config::Config;
use vref_logging::exit::{Blame, Failure};
use vref_record::{Frame, RecordedRay, RecordedSnapshot, RecordingWriter};
use vref_scene::Side;
use vref_view::ViewOptions;
use vref_wire::ipc::{create_node, drain, open_gesture, open_snapshot, termination_requested};

use crate::cli::RecordArgs;

/// Longest sleep between checks of the clock.
const TICK: Duration = Duration::from_millis(100);

pub fn run(args: &RecordArgs) -> Result<(), Failure> {
    let (config, _) = Config::load(args.config.as_deref()).bad_input()?;
    if let Some(path) = &args.ros2 {
        return record_ros2(args, path, &config);
    }
    let out = args
        .out
        .as_deref()
        .ok_or_else(|| anyhow!("--out or --ros2 is needed"))
        .bad_input()?;
    let mcap = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("mcap"));
    if args.images.is_some() && !mcap {
        return Err(anyhow!("--images needs an MCAP file (--out FILE.mcap)")).bad_input();
    }
    if mcap {
        return record_mcap(args, out, &config);
    }
    let partial = out.with_extension("vrec.tmp");
    let file = File::create(&partial)
        .with_context(|| format!("creating {}", partial.display()))
        .bad_input()?;
    let mut writer = RecordingWriter::new(BufWriter::new(file)).runtime()?;
    let frames = record(&config, args.duration, &mut writer).runtime();
    let finished = writer.finish().map(drop).runtime();
    let outcome = frames.and_then(|n| finished.map(|()| n));
    match outcome {
        Ok(frames) => {
            std::fs::rename(&partial, out)
                .with_context(|| format!("renaming {} to {}", partial.display(), out.display()))
                .runtime()?;
            tracing::info!(frames, out = %out.display(), "recorded");
            crate::stdout::print(&format!("{}: {frames} frames\n", out.display()))
        }
        Err(e) => {
            std::fs::remove_file(&partial).ok();
            Err(e)
        }
    }
}

/// An MCAP recording: `vref view`'s channels, the raw wire ones among
/// them, written by vref-view with nothing served.
fn record_mcap(args: &RecordArgs, out: &Path, config: &Config) -> Result<(), Failure> {
    let partial = out.with_extension("mcap.tmp");
    let images = match &args.images {
        Some(dir) => Some(crate::view::load_images(config, dir)?),
        None => None,
    };
    let options = ViewOptions {
        listen: None,
        mcap: Some(partial.clone()),
        duration: Some(args.duration),
        scene_rate_hz: 10.0,
        answer_rate_hz: args.answer_rate.unwrap_or(0.0),
        images,
    };
    match vref_view::run(&config.ipc, &options, |_| {}) {
        Ok(counts) => {
            std::fs::rename(&partial, out)
                .with_context(|| format!("renaming {} to {}", partial.display(), out.display()))
                .runtime()?;
            tracing::info!(messages = counts.total(), out = %out.display(), "recorded");
            crate::stdout::print(&format!(
                "{}: {}\n",
                out.display(),
                crate::view::describe(&counts)
            ))
        }
        Err(e) => {
            std::fs::remove_file(&partial).ok();
            Err(crate::view::blame(e))
        }
    }
}

/// vref-ros2's outputs as ROS 2 messages in MCAP (vref_ros2::record).
fn record_ros2(args: &RecordArgs, out: &Path, config: &Config) -> Result<(), Failure> {
    if !out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("mcap"))
    {
        return Err(anyhow!(
            "--ros2 {}: the file must be named .mcap",
            out.display()
        ))
        .bad_input();
    }
    let partial = out.with_extension("mcap.tmp");
    let file = File::create(&partial)
        .with_context(|| format!("creating {}", partial.display()))
        .bad_input()?;
    let rate = args.answer_rate.unwrap_or(config.ros2.answer_rate_hz);
    match vref_ros2::record::record(config, BufWriter::new(file), args.duration, rate) {
        Ok(counts) => {
            std::fs::rename(&partial, out)
                .with_context(|| format!("renaming {} to {}", partial.display(), out.display()))
                .runtime()?;
            tracing::info!(?counts, out = %out.display(), "recorded");
            crate::stdout::print(&format!(
                "{}: {} marker arrays, {} referenced objects, {} headset poses\n",
                out.display(),
                counts.marker_arrays,
                counts.referenced,
                counts.headset_poses
            ))
        }
        Err(e) => {
            std::fs::remove_file(&partial).ok();
            Err(anyhow::Error::from(e)).runtime()
        }
    }
}

/// Records until `duration` has passed or SIGINT/SIGTERM; returns frames.
fn record(
    config: &Config,
    duration: Duration,
    writer: &mut RecordingWriter<BufWriter<File>>,
) -> anyhow::Result<u64> {
    let ipc = &config.ipc;
    let node = create_node(ipc, &format!("vref-record-{}", std::process::id()))?;
    let (robot_data, robot_event) = open_snapshot(&node, ipc, Side::Robot)?;
    let (human_data, human_event) = open_snapshot(&node, ipc, Side::Human)?;
    let (gesture_data, gesture_event) = open_gesture(&node, ipc)?;
    let err = |what: &'static str| move |e: &dyn std::fmt::Debug| anyhow!("{what}: {e:?}");
    let robot = robot_data
        .subscriber_builder()
        .create()
        .map_err(|e| err("robot subscriber")(&e))?;
    let human = human_data
        .subscriber_builder()
        .create()
        .map_err(|e| err("human subscriber")(&e))?;
    let gesture = gesture_data
        .subscriber_builder()
        .create()
        .map_err(|e| err("gesture subscriber")(&e))?;
    let listeners = [
        robot_event
            .listener_builder()
            .create()
            .map_err(|e| err("listener")(&e))?,
        human_event
            .listener_builder()
            .create()
            .map_err(|e| err("listener")(&e))?,
        gesture_event
            .listener_builder()
            .create()
            .map_err(|e| err("listener")(&e))?,
    ];
    let waitset = WaitSetBuilder::new()
        .create::<ipc::Service>()
        .map_err(|e| err("waitset")(&e))?;
    let _guards = listeners
        .iter()
        .map(|l| waitset.attach_notification(l))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| err("attaching")(&e))?;

    let end = Instant::now() + duration;
    let mut frames = 0u64;
    let mut failure: Option<anyhow::Error> = None;
    while Instant::now() < end && failure.is_none() {
        let wait = (end - Instant::now()).min(TICK);
        let result = waitset
            .wait_and_process_once_with_timeout(|_| CallbackProgression::Continue, wait)
            .map_err(|e| err("waiting")(&e))?;
        if termination_requested(&result) {
            break;
        }
        for l in &listeners {
            l.try_wait(|_| {}).ok();
        }
        let mut write = |frame: Frame| match writer.write(&frame) {
            Ok(()) => frames += 1,
            Err(e) => failure = Some(e.into()),
        };
        // A failed receive is logged and the next turn tries again.
        for (side, sub) in [(Side::Robot, &robot), (Side::Human, &human)] {
            let taken = drain::each(sub, |sample| {
                write(Frame::Snapshot(RecordedSnapshot::from_wire(
                    side,
                    sample.user_header(),
                    sample.payload(),
                )))
            });
            if let Err(e) = taken {
                tracing::warn!(%side, "receiving a snapshot: {e:?}");
            }
        }
        let taken = drain::each(&gesture, |sample| {
            write(Frame::Gesture(RecordedRay::from_wire(sample.payload())))
        });
        if let Err(e) = taken {
            tracing::warn!("receiving a ray: {e:?}");
        }
    }
    match failure {
        Some(e) => Err(e),
        None => Ok(frames),
    }
}
