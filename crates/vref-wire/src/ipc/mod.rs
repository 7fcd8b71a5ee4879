//! Every iceoryx2 service of vref is named and created here, with explicit
//! settings, so that all processes agree on them (a service created first
//! with small settings makes a later open that asks for more fail).

mod client;
mod decision;
pub mod drain;
mod error;
mod names;
mod node;
mod publishers;
mod server;
mod services;
mod settings;
mod stats;
mod watch;

pub use client::ReferenceClient;
pub use decision::{Decision, DecisionError, DecisionPublisher, DecisionReader};
pub use error::IpcError;
pub use names::ServiceNames;
pub use node::{
    Node, SHORTEST_LISTENER_WAIT, create_node, listener_timeout, nap, now_ns, termination_requested,
};
pub use publishers::{GesturePublisher, SnapshotPublisher};
pub use server::{ClientId, ReferenceServer, Served, answer_waiting};
pub use services::{
    AnswerPort, DecisionPort, EventPort, EventQos, GesturePort, Pattern, PublishSubscribeQos,
    ReferencePort, RequestResponseQos, ServiceSpec, SlicePublisherQos, SnapshotPort, StatsPort,
    TypeRef, catalogue, decision_qos, event_qos, gesture_qos, open_answer_event, open_decision,
    open_gesture, open_reference, open_request_event, open_snapshot, open_stats, reference_qos,
    slice_publisher_qos, snapshot_qos, stats_qos,
};
pub use settings::IpcSettings;
pub use stats::{StatsPublisher, StatsReader};
pub use watch::SnapshotWatch;
