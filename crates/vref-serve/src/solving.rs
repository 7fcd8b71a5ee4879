//! The solver thread: takes the newest pair of accepted snapshots the
//! intake posted (pairs posted while it solved are replaced by newer ones,
//! so it always solves the newest), publishes each finished solution for
//! the query path, and the whole decision on the decision service. The
//! WaitSet thread never waits for it.

use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use vref_reference::{
    Latest, Mailbox, Pair, Solved, Solver, decision_entry, decision_header, decision_len,
};
use vref_wire::ipc::{DecisionPublisher, IpcSettings, create_node};

/// What the two threads share.
#[derive(Debug, Default)]
pub struct Handoff {
    /// The newest pair to solve.
    pub jobs: Mailbox<Pair>,
    /// The latest finished solution.
    pub solved: Latest<Solved>,
}

/// How long shutdown waits for a solve in progress.
const JOIN_WITHIN: Duration = Duration::from_secs(5);
/// Failed solves and decisions logged at most this often.
const WARN_EVERY: Duration = Duration::from_secs(10);

#[derive(Debug)]
pub struct SolverThread {
    handoff: Arc<Handoff>,
    thread: Option<JoinHandle<()>>,
}

/// What the thread needs besides the solver.
#[derive(Debug, Clone)]
pub struct Publishing {
    pub ipc: IpcSettings,
    pub nice: i32,
    /// A solve longer than this makes answers stale: said in the log.
    pub budget: Duration,
    pub method: String,
    /// When an entry of the decision is `ok`.
    pub ok_rule: vref_match::OkRule,
}

impl SolverThread {
    pub fn spawn(
        solver: Solver,
        handoff: Arc<Handoff>,
        publishing: Publishing,
    ) -> Result<Self, crate::ServeError> {
        let shared = handoff.clone();
        let thread = std::thread::Builder::new()
            .name("solver".to_owned())
            .spawn(move || solve_until_closed(solver, &shared, &publishing))
            .map_err(crate::ServeError::Thread)?;
        Ok(Self {
            handoff,
            thread: Some(thread),
        })
    }

    /// Stops taking pairs and waits (boundedly) for the solve in progress.
    pub fn stop(mut self) {
        self.handoff.jobs.close();
        let Some(thread) = self.thread.take() else {
            return;
        };
        let deadline = Instant::now() + JOIN_WITHIN;
        while !thread.is_finished() && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(10));
        }
        if thread.is_finished() {
            if thread.join().is_err() {
                tracing::error!("the solver thread panicked");
            }
        } else {
            tracing::warn!(?JOIN_WITHIN, "a solve still running at exit was abandoned");
        }
    }
}

/// Nice value of `rigid`'s full searches apart: only a later solve needs
/// what they find, so they give way to the solves, the queries and the
/// feeds.
const SEARCH_NICE: i32 = 19;

fn lower_search_thread() {
    if let Err(e) = crate::priority::set_this_thread_nice(SEARCH_NICE) {
        tracing::debug!("a full search apart keeps the solver's priority: {e}");
    }
}

fn solve_until_closed(mut solver: Solver, handoff: &Handoff, publishing: &Publishing) {
    if let Err(e) = crate::priority::set_this_thread_nice(publishing.nice) {
        tracing::warn!(
            nice = publishing.nice,
            "the solver thread keeps its priority: {e}"
        );
    }
    solver.on_search_thread(lower_search_thread);
    // Its own node: iceoryx2's ports belong to the thread that made them.
    let decisions = create_node(&publishing.ipc, "vref-matcher-solver")
        .and_then(|node| {
            let publisher = DecisionPublisher::new(&node, &publishing.ipc)?;
            Ok((publisher, node))
        })
        .map_err(|e| tracing::error!("decisions will not be published: {e}"))
        .ok();
    let (mut publisher, _node) = match decisions {
        Some((p, n)) => (Some(p), Some(n)),
        None => (None, None),
    };
    let mut last_warning: Option<Instant> = None;
    let mut warn = |what: &str, error: &dyn std::fmt::Display| {
        if last_warning.is_none_or(|at| at.elapsed() >= WARN_EVERY) {
            last_warning = Some(Instant::now());
            tracing::warn!("{what}: {error}");
        }
    };
    while let Some(pair) = handoff.jobs.take() {
        let solved = match solver.solve(&pair) {
            Ok(solved) => Arc::new(solved),
            Err(e) => {
                warn("solving", &e);
                continue;
            }
        };
        if solved.took > publishing.budget {
            let over = format!(
                "took {} ms, over the freshness budget of {} ms (half of stale_after_ms): answers resting on it turn stale sooner",
                solved.took.as_millis(),
                publishing.budget.as_millis()
            );
            warn("a solve", &over);
        }
        handoff.solved.publish(solved.clone());
        if let Some(publisher) = &mut publisher
            && let Err(e) = publish(publisher, &solved, publishing)
        {
            warn("publishing the decision", &e);
        }
    }
}

fn publish(
    publisher: &mut DecisionPublisher,
    solved: &Solved,
    publishing: &Publishing,
) -> Result<(), vref_wire::ipc::IpcError> {
    publisher.publish(
        decision_header(solved, &publishing.method),
        decision_len(solved),
        |row| decision_entry(solved, row, &publishing.ok_rule),
    )
}
