//! The matcher service's loop, as `vref-feed` holds the feeds' loops. One
//! thread waits on both feeds, the gesture feed and reference requests
//! with one WaitSet: it takes snapshots and rays, answers every query from
//! the latest finished solution and publishes statistics. A second thread
//! solves the newest pair of snapshots whenever one arrives and publishes
//! each decision; a third cleans up after dead nodes (docs/reliability.md). The
//! `vref-matcher` binary parses its arguments and calls [`run`].

mod cleanup;
mod error;
mod priority;
mod reject_log;
mod service;
mod solving;
mod stats;

pub use error::ServeError;
pub use service::run;
