//! What the matcher process knows and how it answers, without IPC: the
//! last valid snapshot of each side and the latest pointing ray, the
//! solution for the current pair of snapshots, and the answer to a
//! reference query. The service binary only moves messages between
//! iceoryx2 and this state, so everything here is tested directly.

mod answer;
mod rejection;
mod settings;
mod state;
mod target;

pub use rejection::{RejectReason, Rejections};
pub use settings::MatcherSettings;
pub use state::{ReferenceState, Rejected};
pub use target::resolve_ray;
