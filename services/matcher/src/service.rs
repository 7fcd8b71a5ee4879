use std::time::{Duration, Instant};

use anyhow::{Context, anyhow};
use iceoryx2::port::listener::Listener;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use vref_config::Config;
use vref_reference::ReferenceState;
use vref_scene::Side;
use vref_wire::ipc::{
    ReferenceServer, StatsPublisher, answer_waiting, create_node, open_answer_event, open_gesture,
    open_reference, open_request_event, open_snapshot,
};
use vref_wire::{ObjectEntry, SnapshotHeader};

use crate::stats::{self, Counters};

/// How often the matcher logs what it has done.
const REPORT_EVERY: Duration = Duration::from_secs(10);

type SnapshotSubscriber = Subscriber<ipc::Service, [ObjectEntry], SnapshotHeader>;

/// Runs until SIGINT or SIGTERM.
pub fn run(config: &Config) -> anyhow::Result<()> {
    let mut state = ReferenceState::new(&config.matcher, config.matching, config.scene.limits())
        .context("matcher configuration")?;
    let ipc = &config.ipc;
    let node = create_node(ipc, "vref-matcher")?;
    // A predecessor killed without cleanup may still hold ports.
    node.try_cleanup_dead_nodes();

    let (robot_data, robot_event) = open_snapshot(&node, ipc, Side::Robot)?;
    let (human_data, human_event) = open_snapshot(&node, ipc, Side::Human)?;
    let (gesture_data, gesture_event) = open_gesture(&node, ipc)?;
    let robot_sub = robot_data
        .subscriber_builder()
        .create()
        .map_err(|e| port_error("robot subscriber", &e))?;
    let human_sub = human_data
        .subscriber_builder()
        .create()
        .map_err(|e| port_error("human subscriber", &e))?;
    let gesture_sub = gesture_data
        .subscriber_builder()
        .create()
        .map_err(|e| port_error("gesture subscriber", &e))?;
    let robot_listener = robot_event
        .listener_builder()
        .create()
        .map_err(|e| port_error("robot listener", &e))?;
    let human_listener = human_event
        .listener_builder()
        .create()
        .map_err(|e| port_error("human listener", &e))?;
    let gesture_listener = gesture_event
        .listener_builder()
        .create()
        .map_err(|e| port_error("gesture listener", &e))?;
    let server = open_reference(&node, ipc)?
        .server_builder()
        .create()
        .map_err(|e| port_error("reference server", &e))?;
    let request_listener = open_request_event(&node, ipc)?
        .listener_builder()
        .create()
        .map_err(|e| port_error("request listener", &e))?;
    let answer_notifier = open_answer_event(&node, ipc)?
        .notifier_builder()
        .create()
        .map_err(|e| port_error("answer notifier", &e))?;
    let stats_publisher = StatsPublisher::new(&node, ipc)?;

    let stale_after = Duration::from_millis(config.matcher.stale_after_ms);
    let waitset = WaitSetBuilder::new()
        .create::<ipc::Service>()
        .map_err(|e| anyhow!("creating the WaitSet: {e:?}"))?;
    let attach = |e: &dyn std::fmt::Debug| anyhow!("attaching to the WaitSet: {e:?}");
    let robot_guard = waitset
        .attach_deadline(&robot_listener, stale_after)
        .map_err(|e| attach(&e))?;
    let human_guard = waitset
        .attach_deadline(&human_listener, stale_after)
        .map_err(|e| attach(&e))?;
    let gesture_guard = waitset
        .attach_notification(&gesture_listener)
        .map_err(|e| attach(&e))?;
    let request_guard = waitset
        .attach_notification(&request_listener)
        .map_err(|e| attach(&e))?;
    let cleanup_guard = waitset
        .attach_interval(Duration::from_millis(config.matcher.cleanup_interval_ms))
        .map_err(|e| attach(&e))?;
    let stats_guard = waitset
        .attach_interval(stats::PUBLISH_EVERY)
        .map_err(|e| attach(&e))?;

    tracing::info!(namespace = %ipc.namespace, method = %config.matcher.method, "matcher ready");
    let mut counters = Counters::new();
    let mut silent = [false; 2];
    let mut last_report = Instant::now();
    let on_event = |id: WaitSetAttachmentId<ipc::Service>| {
        for (side, guard, listener, sub) in [
            (Side::Robot, &robot_guard, &robot_listener, &robot_sub),
            (Side::Human, &human_guard, &human_listener, &human_sub),
        ] {
            let flag = &mut silent[side as usize];
            if id.has_event_from(guard) {
                drain(listener);
                take_snapshot(&mut state, &mut counters, side, sub);
                if *flag {
                    tracing::info!(%side, "feed is back");
                    *flag = false;
                }
            }
            if id.has_missed_deadline(guard) && !*flag {
                tracing::warn!(%side, ?stale_after, "feed silent: answers are stale until it resumes");
                *flag = true;
            }
        }
        if id.has_event_from(&gesture_guard) {
            drain(&gesture_listener);
            take_ray(&mut state, &gesture_sub);
        }
        if id.has_event_from(&request_guard) {
            drain(&request_listener);
        }
        // Requests are served on every wake-up: a client's notification
        // may have been merged with another event.
        let served = serve(&mut state, &mut counters, &server);
        if served > 0
            && let Err(e) = answer_notifier.notify()
        {
            tracing::warn!("notifying answers: {e:?}");
        }
        if id.has_event_from(&cleanup_guard) {
            let cleanup = node.try_cleanup_dead_nodes();
            if cleanup.cleanups > 0 || cleanup.failed_cleanups > 0 {
                tracing::info!(
                    cleaned = cleanup.cleanups,
                    failed = cleanup.failed_cleanups,
                    "dead nodes"
                );
            }
        }
        if id.has_event_from(&stats_guard)
            && let Err(e) = stats_publisher.publish(&counters.message(&state))
        {
            tracing::warn!("publishing statistics: {e}");
        }
        if last_report.elapsed() >= REPORT_EVERY {
            last_report = Instant::now();
            tracing::info!(
                answered = counters.answered(),
                solves = state.solves(),
                rejected = state.rejections().total(),
                "status"
            );
        }
        CallbackProgression::Continue
    };
    let result = waitset
        .wait_and_process(on_event)
        .map_err(|e| anyhow!("waiting: {e:?}"))?;
    tracing::info!(
        ?result,
        answered = counters.answered(),
        solves = state.solves(),
        "matcher stopped"
    );
    for (reason, count) in state.rejections().nonzero() {
        tracing::info!(%reason, count, "rejected");
    }
    Ok(())
}

fn drain(listener: &Listener<ipc::Service>) {
    if let Err(e) = listener.try_wait(|_| {}) {
        tracing::warn!("draining a listener: {e:?}");
    }
}

/// Validates the newest snapshot in place and hands it to the state.
fn take_snapshot(
    state: &mut ReferenceState,
    counters: &mut Counters,
    side: Side,
    sub: &SnapshotSubscriber,
) {
    let mut latest = None;
    loop {
        match sub.receive() {
            Ok(Some(sample)) => latest = Some(sample),
            Ok(None) => break,
            Err(e) => {
                tracing::warn!(%side, "receiving a snapshot: {e:?}");
                break;
            }
        }
    }
    let Some(sample) = latest else {
        return;
    };
    let accepted =
        state.accept_snapshot(side, sample.user_header(), sample.payload(), Instant::now());
    counters.snapshot(side, accepted.is_ok());
    if let Err(rejected) = accepted {
        tracing::warn!(%side, reason = %rejected.reason, "rejected snapshot: {}", rejected.detail);
    }
}

fn take_ray(
    state: &mut ReferenceState,
    sub: &Subscriber<ipc::Service, vref_wire::PointingRay, ()>,
) {
    loop {
        match sub.receive() {
            Ok(Some(sample)) => {
                if let Err(rejected) = state.accept_ray(sample.payload()) {
                    tracing::warn!(reason = %rejected.reason, "rejected ray: {}", rejected.detail);
                }
            }
            Ok(None) => break,
            Err(e) => {
                tracing::warn!("receiving a ray: {e:?}");
                break;
            }
        }
    }
}

/// Answers every waiting request; returns how many.
fn serve(state: &mut ReferenceState, counters: &mut Counters, server: &ReferenceServer) -> u64 {
    let served = answer_waiting(
        server,
        |query| state.answer(query, Instant::now()),
        |answer| counters.answer(answer.status()),
    );
    for failure in &served.failures {
        tracing::warn!("{failure}");
    }
    served.sent
}

fn port_error(what: &str, error: &dyn std::fmt::Debug) -> anyhow::Error {
    anyhow!("creating {what}: {error:?}")
}
