//! What the matcher process knows and how it answers, without IPC: the
//! intake (the newest valid snapshot of each side and pointing ray, with
//! the rules on stamps and sequences that keep one message from stalling
//! or locking a feed), the solve as a separate step ([`Solver`], which the
//! service runs on its own thread) and the hand-off between the two
//! ([`Mailbox`], [`Latest`]), the answer to a reference query from the
//! latest finished solution, the published decision, each client's share
//! of the matcher ([`QueryRate`]) and whether a configuration can solve
//! within its freshness budget ([`check_budget`]). The service binary only
//! moves messages between iceoryx2 and these, so everything here is
//! tested directly.

mod answer;
mod budget;
mod decision;
mod handoff;
mod rate;
mod rejection;
mod sequence;
mod settings;
mod solver;
mod stamp;
mod state;
mod target;

pub use answer::outcome;
pub use budget::{OverBudget, check_budget, estimated_solve_ms, freshness_budget_ms};
pub use decision::{decision_entry, decision_header, decision_len};
pub use handoff::{Latest, Mailbox};
pub use rate::{Client, QueryRate};
pub use rejection::{RejectReason, Rejections};
pub use sequence::{MAX_JUMP, MAX_RATE_PER_MS, Origin, Placement, Sequencer};
pub use settings::MatcherSettings;
pub use solver::{Pair, Solved, Solver};
pub use stamp::{Now, capture_age};
pub use state::{Accepted, ReferenceState, Rejected};
pub use target::{Pointed, resolve_ray};
