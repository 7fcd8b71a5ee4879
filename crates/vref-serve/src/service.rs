use std::sync::Arc;
use std::time::{Duration, Instant};

use iceoryx2::port::listener::Listener;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use iceoryx2::waitset::WaitSetRunResult;
use vref_config::Config;
use vref_reference::{Now, Placement, QueryRate, ReferenceState, RejectReason, Rejected, Solver};
use vref_scene::Side;
use vref_wire::ipc::{
    ReferenceServer, StatsPublisher, answer_waiting, create_node, drain, open_answer_event,
    open_gesture, open_reference, open_request_event, open_snapshot,
};
use vref_wire::{ObjectEntry, PointingRay, SnapshotHeader};

use crate::ServeError;
use crate::cleanup::CleanupThread;
use crate::reject_log::RejectLog;
use crate::solving::{Handoff, Publishing, SolverThread};
use crate::stats::{self, Counters};

/// How often the matcher logs what it has done, and sums up the
/// rejections it did not log one by one.
const REPORT_EVERY: Duration = Duration::from_secs(10);

type SnapshotSubscriber = Subscriber<ipc::Service, [ObjectEntry], SnapshotHeader>;
type GestureSubscriber = Subscriber<ipc::Service, PointingRay, ()>;

/// What the WaitSet thread works on.
struct Intake {
    state: ReferenceState,
    counters: Counters,
    rejections: RejectLog,
    rate: QueryRate,
    handoff: Arc<Handoff>,
    /// Version of the solution installed last.
    installed: u64,
}

/// Runs until SIGINT or SIGTERM.
pub fn run(config: &Config) -> Result<(), ServeError> {
    let state = ReferenceState::new(&config.matcher, config.scene.limits())?;
    let solver = Solver::new(&config.matcher, config.matching)?;
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
        .map_err(|e| waitset_error("creating the WaitSet", &e))?;
    let attach = |e: &dyn std::fmt::Debug| waitset_error("attaching to the WaitSet", e);
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
    let stats_guard = waitset
        .attach_interval(stats::PUBLISH_EVERY)
        .map_err(|e| attach(&e))?;

    let handoff = Arc::new(Handoff::default());
    let solver_thread = SolverThread::spawn(
        solver,
        handoff.clone(),
        Publishing {
            ipc: ipc.clone(),
            nice: config.matcher.solver_nice,
            budget: Duration::from_millis(vref_reference::freshness_budget_ms(&config.matcher)),
            method: config.matcher.method.clone(),
            ok_rule: config.matcher.ok_rule(),
        },
    )?;
    let cleanup_thread = CleanupThread::spawn(
        ipc.clone(),
        Duration::from_millis(config.matcher.cleanup_interval_ms),
        config.matcher.solver_nice,
    )?;
    let mut intake = Intake {
        state,
        counters: Counters::new(),
        rejections: RejectLog::new(REPORT_EVERY, Instant::now()),
        // Room for every client and as many dead ones.
        rate: QueryRate::new(
            config.matcher.max_queries_per_client_hz,
            2 * ipc.max_clients,
        ),
        handoff,
        installed: 0,
    };
    tracing::info!(
        namespace = %ipc.namespace,
        method = %config.matcher.method,
        tier = %config.matcher.tier,
        "matcher ready"
    );
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
                intake.take_snapshot(side, sub);
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
        }
        if id.has_event_from(&request_guard) {
            drain(&request_listener);
        }
        // Every ray sent so far, whichever event woke us: a latest-gesture
        // query sent after a ray must be answered with it, also when the
        // ray's notification is handled later in this wake-up (its
        // attachment after the one in hand). Taken only on its own event,
        // a query sent with its ray was answered with the previous ray
        // (clients/python/tests/test_layout_client.py).
        intake.take_rays(&gesture_sub);
        // The newest finished solve, then every waiting request: a
        // client's notification may have been merged with another event.
        let retired = intake.install_newest();
        let served = intake.serve(&server);
        if served > 0
            && let Err(e) = answer_notifier.notify()
        {
            tracing::warn!("notifying answers: {e:?}");
        }
        // Freed after the answers went out.
        drop(retired);
        if id.has_event_from(&stats_guard)
            && let Err(e) = stats_publisher.publish(&intake.counters.message(&intake.state))
        {
            tracing::warn!("publishing statistics: {e}");
        }
        intake.summarise_rejections();
        if last_report.elapsed() >= REPORT_EVERY {
            last_report = Instant::now();
            tracing::info!(
                answered = intake.counters.answered(),
                solves = intake.state.solves(),
                coalesced = intake.handoff.jobs.coalesced(),
                rejected = intake.state.rejections().total(),
                "status"
            );
        }
        CallbackProgression::Continue
    };
    // A signal that asks nothing (SIGCONT after SIGSTOP) ends a run as
    // `Interrupt`: the matcher goes on, and stops on a termination request.
    let mut on_event = on_event;
    let result = loop {
        match waitset.wait_and_process(&mut on_event) {
            Ok(WaitSetRunResult::Interrupt) => continue,
            other => break other.map_err(|e| waitset_error("waiting", &e)),
        }
    };
    solver_thread.stop();
    cleanup_thread.stop();
    let result = result?;
    tracing::info!(
        ?result,
        answered = intake.counters.answered(),
        solves = intake.state.solves(),
        "matcher stopped"
    );
    for (reason, count) in intake.state.rejections().nonzero() {
        tracing::info!(%reason, count, "rejected");
    }
    Ok(())
}

impl Intake {
    /// Validates the newest snapshot in place and hands it to the state;
    /// a new one goes to the solver.
    fn take_snapshot(&mut self, side: Side, sub: &SnapshotSubscriber) {
        let drained = drain::newest(sub);
        if let Some(e) = &drained.error {
            tracing::warn!(%side, "receiving a snapshot: {e:?}");
        }
        let Some(sample) = drained.newest else {
            return;
        };
        let origin = sample.header().publisher_id().value();
        let accepted = self.state.accept_snapshot(
            side,
            origin,
            sample.user_header(),
            sample.payload(),
            &Now::read(),
        );
        self.counters.snapshot(side, accepted.is_ok());
        let service = match side {
            Side::Robot => "robot snapshot",
            Side::Human => "human snapshot",
        };
        match accepted {
            Ok(a) => {
                note_placement(service, a.placement, sample.user_header().session);
                if let Some(pair) = self.state.latest_pair() {
                    self.handoff.jobs.post(pair);
                }
            }
            Err(rejected) => self.log_rejection(service, origin, &rejected),
        }
    }

    fn take_rays(&mut self, sub: &GestureSubscriber) {
        let taken = drain::each(sub, |sample| {
            let origin = sample.header().publisher_id().value();
            match self
                .state
                .accept_ray(origin, sample.payload(), &Now::read())
            {
                Ok(a) => note_placement("ray", a.placement, sample.payload().session),
                Err(rejected) => self.log_rejection("ray", origin, &rejected),
            }
        });
        if let Err(e) = taken {
            tracing::warn!("receiving a ray: {e:?}");
        }
    }

    /// Makes the newest finished solution the one queries read; returns
    /// the one it replaced, to be freed after serving.
    fn install_newest(&mut self) -> Option<Arc<vref_reference::Solved>> {
        let (version, solved) = self.handoff.solved.newer_than(self.installed)?;
        self.installed = version;
        self.state.install(solved)
    }

    /// Answers every waiting request; returns how many.
    fn serve(&mut self, server: &ReferenceServer) -> u64 {
        let Self {
            state,
            counters,
            rejections,
            rate,
            ..
        } = self;
        let served = answer_waiting(
            server,
            |query, client| {
                let now = Now::read();
                if rate.allow(client, now.instant) {
                    return Some(state.answer(query, &now));
                }
                state.count_rejection(RejectReason::QueryOverRate);
                if rejections.note("query", RejectReason::QueryOverRate, client) {
                    tracing::warn!(
                        reason = %RejectReason::QueryOverRate,
                        client = format_args!("{client:032x}"),
                        "dropped a query: the client is over [matcher] max_queries_per_client_hz"
                    );
                }
                None
            },
            |answer| counters.answer(answer.status()),
        );
        for failure in &served.failures {
            tracing::warn!("{failure}");
        }
        served.sent
    }

    fn log_rejection(&mut self, service: &'static str, origin: u128, rejected: &Rejected) {
        if self.rejections.note(service, rejected.reason, origin) {
            tracing::warn!(
                reason = %rejected.reason,
                publisher = format_args!("{origin:032x}"),
                "rejected {service}: {}",
                rejected.detail
            );
        }
    }

    fn summarise_rejections(&mut self) {
        let Some((summary, overflow)) = self.rejections.flush(Instant::now()) else {
            return;
        };
        let interval = self.rejections.interval();
        for s in summary {
            tracing::warn!(
                reason = %s.reason,
                count = s.count,
                ?interval,
                "{} more of {} rejected for this reason in the last interval",
                s.count,
                s.service
            );
        }
        if overflow > 0 {
            tracing::warn!(
                count = overflow,
                ?interval,
                "more rejections from other publishers"
            );
        }
    }
}

/// New sessions and resynchronised ports are worth a line; the next
/// message of a session is not.
fn note_placement(service: &str, placement: Placement, session: u64) {
    match placement {
        Placement::Next => {}
        Placement::NewPort | Placement::NewSession => {
            tracing::info!(
                session = format_args!("{session:016x}"),
                "{service}: new session"
            );
        }
        Placement::Resync => tracing::warn!(
            session = format_args!("{session:016x}"),
            "{service}: publisher taken again after its messages were refused as out of order"
        ),
    }
}

fn drain(listener: &Listener<ipc::Service>) {
    if let Err(e) = listener.try_wait(|_| {}) {
        tracing::warn!("draining a listener: {e:?}");
    }
}

fn port_error(what: &'static str, error: &dyn std::fmt::Debug) -> ServeError {
    ServeError::Port {
        what,
        detail: format!("{error:?}"),
    }
}

fn waitset_error(what: &'static str, error: &dyn std::fmt::Debug) -> ServeError {
    ServeError::WaitSet {
        what,
        detail: format!("{error:?}"),
    }
}
