use iceoryx2::prelude::*;
use iceoryx2::service::port_factory::{event, publish_subscribe, request_response};
use vref_scene::Side;

use super::error::{IpcError, iceoryx_err};
use super::{IpcSettings, Node, ServiceNames};
use crate::{
    DecisionEntry, DecisionHeader, MatcherStats, ObjectEntry, PointingRay, ReferenceAnswer,
    ReferenceQuery, SnapshotHeader,
};

pub type SnapshotPort = publish_subscribe::PortFactory<ipc::Service, [ObjectEntry], SnapshotHeader>;
pub type GesturePort = publish_subscribe::PortFactory<ipc::Service, PointingRay, ()>;
pub type ReferencePort =
    request_response::PortFactory<ipc::Service, ReferenceQuery, (), ReferenceAnswer, ()>;
pub type EventPort = event::PortFactory<ipc::Service>;
pub type StatsPort = publish_subscribe::PortFactory<ipc::Service, MatcherStats, ()>;
pub type AnswerPort = EventPort;
pub type DecisionPort =
    publish_subscribe::PortFactory<ipc::Service, [DecisionEntry], DecisionHeader>;

/// Event id sent when a notifier's process was found dead and cleaned up.
pub const NOTIFIER_DEAD: usize = 7;
/// Restarted processes may meet a dead predecessor's ports until cleanup:
/// room for both.
const PORTS_PER_ROLE: usize = 4;

fn service_name(name: &str) -> Result<ServiceName, IpcError> {
    ServiceName::new(name).map_err(|_| IpcError::BadName {
        what: "service name",
        value: name.to_owned(),
    })
}

fn open_event(node: &Node, settings: &IpcSettings, name: &str) -> Result<EventPort, IpcError> {
    let notifiers = settings.max_clients + PORTS_PER_ROLE;
    let listeners = settings.max_subscribers.max(settings.max_clients) + PORTS_PER_ROLE;
    node.service_builder(&service_name(name)?)
        .event()
        .max_notifiers(notifiers)
        .max_listeners(listeners)
        // Every notifier and listener may be a node of its own; iceoryx2's
        // default (36) would cap the clients below [ipc] max_clients.
        .max_nodes(notifiers + listeners)
        .notifier_dead_event(EventId::new(NOTIFIER_DEAD))
        .open_or_create()
        .map_err(|e| open_err(settings, format!("opening event service {name}"), e))
}

/// An error opening a service; one whose node limit is reached says so
/// with the setting that sizes it.
fn open_err(settings: &IpcSettings, what: String, error: impl std::fmt::Debug) -> IpcError {
    if format!("{error:?}").contains("ExceedsMaxNumberOfNodes") {
        return IpcError::TooManyClients {
            limit: settings.max_clients,
        };
    }
    iceoryx_err(what, error)
}

/// One side's snapshots (latest wins) and the event that announces them.
pub fn open_snapshot(
    node: &Node,
    settings: &IpcSettings,
    side: Side,
) -> Result<(SnapshotPort, EventPort), IpcError> {
    let name = ServiceNames::new(&settings.namespace).snapshot(side);
    let data = node
        .service_builder(&service_name(&name)?)
        .publish_subscribe::<[ObjectEntry]>()
        .user_header::<SnapshotHeader>()
        .history_size(1)
        .subscriber_max_buffer_size(1)
        .subscriber_max_borrowed_samples(2)
        .enable_safe_overflow(true)
        .max_publishers(PORTS_PER_ROLE)
        .max_subscribers(settings.max_subscribers)
        .max_nodes(PORTS_PER_ROLE + settings.max_subscribers)
        .open_or_create()
        .map_err(|e| open_err(settings, format!("opening {name}"), e))?;
    let event = open_event(node, settings, &ServiceNames::event_of(&name))?;
    Ok((data, event))
}

/// Pointing rays (latest wins) and their event.
pub fn open_gesture(
    node: &Node,
    settings: &IpcSettings,
) -> Result<(GesturePort, EventPort), IpcError> {
    let name = ServiceNames::new(&settings.namespace).gesture();
    let data = node
        .service_builder(&service_name(&name)?)
        .publish_subscribe::<PointingRay>()
        .history_size(1)
        .subscriber_max_buffer_size(1)
        .enable_safe_overflow(true)
        .max_publishers(PORTS_PER_ROLE)
        .max_subscribers(settings.max_subscribers)
        .max_nodes(PORTS_PER_ROLE + settings.max_subscribers)
        .open_or_create()
        .map_err(|e| open_err(settings, format!("opening {name}"), e))?;
    let event = open_event(node, settings, &ServiceNames::event_of(&name))?;
    Ok((data, event))
}

/// Reference queries (request/response). Exactly `[ipc] max_clients`
/// clients may connect: a controller killed without cleanup holds its
/// place only until the next cleanup of dead nodes, which every client
/// runs before connecting.
pub fn open_reference(node: &Node, settings: &IpcSettings) -> Result<ReferencePort, IpcError> {
    let name = ServiceNames::new(&settings.namespace).reference();
    node.service_builder(&service_name(&name)?)
        .request_response::<ReferenceQuery, ReferenceAnswer>()
        .max_clients(settings.max_clients)
        .max_servers(PORTS_PER_ROLE)
        .max_nodes(settings.max_clients + PORTS_PER_ROLE)
        .max_active_requests_per_client(2)
        .max_response_buffer_size(2)
        .enable_safe_overflow_for_requests(true)
        .enable_safe_overflow_for_responses(true)
        .open_or_create()
        .map_err(|e| open_err(settings, format!("opening {name}"), e))
}

/// Signalled by clients after sending a request, so the matcher wakes.
pub fn open_request_event(node: &Node, settings: &IpcSettings) -> Result<EventPort, IpcError> {
    let name = ServiceNames::new(&settings.namespace).reference();
    open_event(node, settings, &ServiceNames::event_of(&name))
}

/// Signalled by the matcher after sending answers, so clients wake.
pub fn open_answer_event(node: &Node, settings: &IpcSettings) -> Result<AnswerPort, IpcError> {
    open_event(
        node,
        settings,
        &ServiceNames::new(&settings.namespace).answers(),
    )
}

/// The matcher's statistics (latest wins; a late subscriber gets the last
/// one published). No event: readers poll.
pub fn open_stats(node: &Node, settings: &IpcSettings) -> Result<StatsPort, IpcError> {
    let name = ServiceNames::new(&settings.namespace).matcher_stats();
    node.service_builder(&service_name(&name)?)
        .publish_subscribe::<MatcherStats>()
        .history_size(1)
        .subscriber_max_buffer_size(1)
        .enable_safe_overflow(true)
        .max_publishers(PORTS_PER_ROLE)
        .max_subscribers(settings.max_subscribers + settings.max_clients)
        .max_nodes(PORTS_PER_ROLE + settings.max_subscribers + settings.max_clients)
        .open_or_create()
        .map_err(|e| open_err(settings, format!("opening {name}"), e))
}

/// The matcher's decision after each solve (latest wins) and its event.
pub fn open_decision(
    node: &Node,
    settings: &IpcSettings,
) -> Result<(DecisionPort, EventPort), IpcError> {
    let name = ServiceNames::new(&settings.namespace).decision();
    let data = node
        .service_builder(&service_name(&name)?)
        .publish_subscribe::<[DecisionEntry]>()
        .user_header::<DecisionHeader>()
        .history_size(1)
        .subscriber_max_buffer_size(1)
        .subscriber_max_borrowed_samples(2)
        .enable_safe_overflow(true)
        .max_publishers(PORTS_PER_ROLE)
        .max_subscribers(settings.max_subscribers + settings.max_clients)
        .max_nodes(PORTS_PER_ROLE + settings.max_subscribers + settings.max_clients)
        .open_or_create()
        .map_err(|e| open_err(settings, format!("opening {name}"), e))?;
    let event = open_event(node, settings, &ServiceNames::event_of(&name))?;
    Ok((data, event))
}
