//! Every iceoryx2 service of vref is named and created here, with explicit
//! settings, so that all processes agree on them (a service created first
//! with small settings makes a later open that asks for more fail).

mod client;
mod decision;
mod error;
mod names;
mod node;
mod publishers;
mod server;
mod services;
mod settings;
mod stats;

pub use client::ReferenceClient;
pub use decision::{Decision, DecisionError, DecisionPublisher, DecisionReader};
pub use error::IpcError;
pub use names::ServiceNames;
pub use node::{Node, create_node, now_ns};
pub use publishers::{GesturePublisher, SnapshotPublisher};
pub use server::{ClientId, ReferenceServer, Served, answer_waiting};
pub use services::{
    AnswerPort, DecisionPort, EventPort, GesturePort, ReferencePort, SnapshotPort, StatsPort,
    open_answer_event, open_decision, open_gesture, open_reference, open_request_event,
    open_snapshot, open_stats,
};
pub use settings::IpcSettings;
pub use stats::{StatsPublisher, StatsReader};
