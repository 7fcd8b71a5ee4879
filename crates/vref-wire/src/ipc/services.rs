//! Every service of vref, created from settings that are data: the
//! `*_qos` functions below are what the `open_*` functions apply and what
//! [`catalogue`] describes (and `vref wire-layout` prints), so the two
//! cannot drift. A setting not named here is iceoryx2 0.10's default.

use std::fmt::Debug;

use iceoryx2::prelude::*;
use iceoryx2::service::builder::publish_subscribe::Builder as PubSubBuilder;
use iceoryx2::service::port_factory::{event, publish_subscribe, request_response};
use serde::Serialize;
use vref_scene::Side;

use super::error::{IpcError, iceoryx_err};
use super::{IpcSettings, Node, ServiceNames};
use crate::layout::type_name_of;
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

/// How a publish-subscribe service is created.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct PublishSubscribeQos {
    pub history_size: usize,
    pub subscriber_max_buffer_size: usize,
    /// `None`: iceoryx2's default (2).
    pub subscriber_max_borrowed_samples: Option<usize>,
    pub enable_safe_overflow: bool,
    pub max_publishers: usize,
    pub max_subscribers: usize,
    /// Nodes that may hold ports of the service at once.
    pub max_nodes: usize,
}

impl PublishSubscribeQos {
    fn apply<P: Debug + IceoryxSend + ?Sized, H: Debug + ZeroCopySend>(
        &self,
        builder: PubSubBuilder<P, H, ipc::Service>,
    ) -> PubSubBuilder<P, H, ipc::Service> {
        let builder = builder
            .history_size(self.history_size)
            .subscriber_max_buffer_size(self.subscriber_max_buffer_size)
            .enable_safe_overflow(self.enable_safe_overflow)
            .max_publishers(self.max_publishers)
            .max_subscribers(self.max_subscribers)
            .max_nodes(self.max_nodes);
        match self.subscriber_max_borrowed_samples {
            Some(n) => builder.subscriber_max_borrowed_samples(n),
            None => builder,
        }
    }
}

/// How vref's publishers of a slice service are created.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct SlicePublisherQos {
    /// Entries the first data segment is sized for.
    pub initial_max_slice_len: usize,
    /// How the segment grows for a longer loan (printed as
    /// `power_of_two`, `best_fit` or `static`).
    #[serde(serialize_with = "strategy_name")]
    pub allocation_strategy: AllocationStrategy,
}

fn strategy_name<S: serde::Serializer>(
    strategy: &AllocationStrategy,
    serializer: S,
) -> Result<S::Ok, S::Error> {
    serializer.serialize_str(match strategy {
        AllocationStrategy::BestFit => "best_fit",
        AllocationStrategy::PowerOfTwo => "power_of_two",
        AllocationStrategy::Static => "static",
    })
}

/// How an event service is created.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct EventQos {
    pub max_notifiers: usize,
    pub max_listeners: usize,
    /// Event id that wakes the listeners when a notifier's process was
    /// found dead.
    pub notifier_dead_event: usize,
    /// Every notifier and listener may be a node of its own; iceoryx2's
    /// default (36) would cap the clients below `[ipc] max_clients`.
    pub max_nodes: usize,
}

/// How the request-response service is created.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct RequestResponseQos {
    pub max_clients: usize,
    pub max_servers: usize,
    pub max_active_requests_per_client: usize,
    pub max_response_buffer_size: usize,
    pub enable_safe_overflow_for_requests: bool,
    pub enable_safe_overflow_for_responses: bool,
    pub max_nodes: usize,
}

/// Latest-wins snapshots of one view.
pub fn snapshot_qos(settings: &IpcSettings) -> PublishSubscribeQos {
    PublishSubscribeQos {
        history_size: 1,
        subscriber_max_buffer_size: 1,
        subscriber_max_borrowed_samples: Some(2),
        enable_safe_overflow: true,
        max_publishers: PORTS_PER_ROLE,
        max_subscribers: settings.max_subscribers,
        max_nodes: PORTS_PER_ROLE + settings.max_subscribers,
    }
}

/// Latest-wins pointing rays.
pub fn gesture_qos(settings: &IpcSettings) -> PublishSubscribeQos {
    PublishSubscribeQos {
        history_size: 1,
        subscriber_max_buffer_size: 1,
        subscriber_max_borrowed_samples: None,
        enable_safe_overflow: true,
        max_publishers: PORTS_PER_ROLE,
        max_subscribers: settings.max_subscribers,
        max_nodes: PORTS_PER_ROLE + settings.max_subscribers,
    }
}

/// The matcher's statistics: read by monitors and controllers alike.
pub fn stats_qos(settings: &IpcSettings) -> PublishSubscribeQos {
    PublishSubscribeQos {
        history_size: 1,
        subscriber_max_buffer_size: 1,
        subscriber_max_borrowed_samples: None,
        enable_safe_overflow: true,
        max_publishers: PORTS_PER_ROLE,
        max_subscribers: settings.max_subscribers + settings.max_clients,
        max_nodes: PORTS_PER_ROLE + settings.max_subscribers + settings.max_clients,
    }
}

/// The matcher's decisions: read by viewers and controllers alike.
pub fn decision_qos(settings: &IpcSettings) -> PublishSubscribeQos {
    PublishSubscribeQos {
        subscriber_max_borrowed_samples: Some(2),
        ..stats_qos(settings)
    }
}

/// Publishers of snapshots and decisions.
pub fn slice_publisher_qos(settings: &IpcSettings) -> SlicePublisherQos {
    SlicePublisherQos {
        initial_max_slice_len: settings.initial_objects.max(1),
        allocation_strategy: AllocationStrategy::PowerOfTwo,
    }
}

/// Every event service (each paired with a data service).
pub fn event_qos(settings: &IpcSettings) -> EventQos {
    let max_notifiers = settings.max_clients + PORTS_PER_ROLE;
    let max_listeners = settings.max_subscribers.max(settings.max_clients) + PORTS_PER_ROLE;
    EventQos {
        max_notifiers,
        max_listeners,
        notifier_dead_event: NOTIFIER_DEAD,
        max_nodes: max_notifiers + max_listeners,
    }
}

/// Reference queries and answers.
pub fn reference_qos(settings: &IpcSettings) -> RequestResponseQos {
    RequestResponseQos {
        // Exactly [ipc] max_clients: the one past it is told so.
        max_clients: settings.max_clients,
        max_servers: PORTS_PER_ROLE,
        max_active_requests_per_client: 2,
        max_response_buffer_size: 2,
        enable_safe_overflow_for_requests: true,
        enable_safe_overflow_for_responses: true,
        max_nodes: settings.max_clients + PORTS_PER_ROLE,
    }
}

fn service_name(name: &str) -> Result<ServiceName, IpcError> {
    ServiceName::new(name).map_err(|_| IpcError::BadName {
        what: "service name",
        value: name.to_owned(),
    })
}

fn open_event(node: &Node, settings: &IpcSettings, name: &str) -> Result<EventPort, IpcError> {
    let qos = event_qos(settings);
    node.service_builder(&service_name(name)?)
        .event()
        .max_notifiers(qos.max_notifiers)
        .max_listeners(qos.max_listeners)
        .notifier_dead_event(EventId::new(qos.notifier_dead_event))
        .max_nodes(qos.max_nodes)
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
    let builder = node
        .service_builder(&service_name(&name)?)
        .publish_subscribe::<[ObjectEntry]>()
        .user_header::<SnapshotHeader>();
    let data = snapshot_qos(settings)
        .apply(builder)
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
    let builder = node
        .service_builder(&service_name(&name)?)
        .publish_subscribe::<PointingRay>();
    let data = gesture_qos(settings)
        .apply(builder)
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
    let qos = reference_qos(settings);
    node.service_builder(&service_name(&name)?)
        .request_response::<ReferenceQuery, ReferenceAnswer>()
        .max_clients(qos.max_clients)
        .max_servers(qos.max_servers)
        .max_active_requests_per_client(qos.max_active_requests_per_client)
        .max_response_buffer_size(qos.max_response_buffer_size)
        .enable_safe_overflow_for_requests(qos.enable_safe_overflow_for_requests)
        .enable_safe_overflow_for_responses(qos.enable_safe_overflow_for_responses)
        .max_nodes(qos.max_nodes)
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
    let builder = node
        .service_builder(&service_name(&name)?)
        .publish_subscribe::<MatcherStats>();
    stats_qos(settings)
        .apply(builder)
        .open_or_create()
        .map_err(|e| open_err(settings, format!("opening {name}"), e))
}

/// The matcher's decision after each solve (latest wins) and its event.
pub fn open_decision(
    node: &Node,
    settings: &IpcSettings,
) -> Result<(DecisionPort, EventPort), IpcError> {
    let name = ServiceNames::new(&settings.namespace).decision();
    let builder = node
        .service_builder(&service_name(&name)?)
        .publish_subscribe::<[DecisionEntry]>()
        .user_header::<DecisionHeader>();
    let data = decision_qos(settings)
        .apply(builder)
        .open_or_create()
        .map_err(|e| open_err(settings, format!("opening {name}"), e))?;
    let event = open_event(node, settings, &ServiceNames::event_of(&name))?;
    Ok((data, event))
}

/// A payload or header type as a service declares it to iceoryx2.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct TypeRef {
    pub type_name: &'static str,
    /// `fixed_size` (one value) or `dynamic` (a slice of values).
    pub variant: &'static str,
    /// Of one value (one slice element).
    pub size: usize,
    pub align: usize,
}

fn fixed<T: ZeroCopySend>() -> TypeRef {
    TypeRef {
        type_name: type_name_of::<T>(),
        variant: "fixed_size",
        size: std::mem::size_of::<T>(),
        align: std::mem::align_of::<T>(),
    }
}

fn slice_of<T: ZeroCopySend>() -> TypeRef {
    TypeRef {
        variant: "dynamic",
        ..fixed::<T>()
    }
}

/// What a service is for, by messaging pattern.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(tag = "pattern", rename_all = "snake_case")]
pub enum Pattern {
    PublishSubscribe {
        payload: TypeRef,
        /// `None`: no user header (`()`).
        user_header: Option<TypeRef>,
        qos: PublishSubscribeQos,
        /// How vref's own publishers are created, for slice services.
        publisher: Option<SlicePublisherQos>,
        /// The event service notified after each sample; `None`: readers
        /// poll.
        event: Option<String>,
    },
    RequestResponse {
        request: TypeRef,
        response: TypeRef,
        qos: RequestResponseQos,
        /// Notified by a client after each request.
        request_event: String,
        /// Notified by the server after it sent answers.
        response_event: String,
    },
    Event {
        qos: EventQos,
        /// Who notifies, and when.
        notifier: &'static str,
        /// Who listens.
        listener: &'static str,
    },
}

/// One of vref's services.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ServiceSpec {
    /// A stable short name, e.g. `robot_snapshot`.
    pub role: &'static str,
    /// The iceoryx2 service name under the settings' namespace.
    pub name: String,
    #[serde(flatten)]
    pub pattern: Pattern,
}

/// Every service of vref under `settings`' namespace, with the settings
/// the `open_*` functions create it with.
pub fn catalogue(settings: &IpcSettings) -> Vec<ServiceSpec> {
    let names = ServiceNames::new(&settings.namespace);
    let event = |role, name: String, notifier, listener| ServiceSpec {
        role,
        name,
        pattern: Pattern::Event {
            qos: event_qos(settings),
            notifier,
            listener,
        },
    };
    let mut services = Vec::new();
    for (side, role, event_role, feed) in [
        (
            Side::Robot,
            "robot_snapshot",
            "robot_snapshot_event",
            "the perception feed, after each snapshot",
        ),
        (
            Side::Human,
            "human_snapshot",
            "human_snapshot_event",
            "the gesture feed, after each snapshot",
        ),
    ] {
        let name = names.snapshot(side);
        let event_name = ServiceNames::event_of(&name);
        services.push(ServiceSpec {
            role,
            name,
            pattern: Pattern::PublishSubscribe {
                payload: slice_of::<ObjectEntry>(),
                user_header: Some(fixed::<SnapshotHeader>()),
                qos: snapshot_qos(settings),
                publisher: Some(slice_publisher_qos(settings)),
                event: Some(event_name.clone()),
            },
        });
        services.push(event(event_role, event_name, feed, "the matcher"));
    }
    let gesture = names.gesture();
    let gesture_event = ServiceNames::event_of(&gesture);
    services.push(ServiceSpec {
        role: "gesture",
        name: gesture,
        pattern: Pattern::PublishSubscribe {
            payload: fixed::<PointingRay>(),
            user_header: None,
            qos: gesture_qos(settings),
            publisher: None,
            event: Some(gesture_event.clone()),
        },
    });
    services.push(event(
        "gesture_event",
        gesture_event,
        "the gesture feed, after each ray",
        "the matcher",
    ));
    let reference = names.reference();
    let request_event = ServiceNames::event_of(&reference);
    services.push(ServiceSpec {
        role: "reference",
        name: reference,
        pattern: Pattern::RequestResponse {
            request: fixed::<ReferenceQuery>(),
            response: fixed::<ReferenceAnswer>(),
            qos: reference_qos(settings),
            request_event: request_event.clone(),
            response_event: names.answers(),
        },
    });
    services.push(event(
        "request_event",
        request_event,
        "a client, after each request",
        "the matcher",
    ));
    services.push(event(
        "answer_event",
        names.answers(),
        "the matcher, after it sent answers",
        "clients waiting for an answer",
    ));
    services.push(ServiceSpec {
        role: "matcher_stats",
        name: names.matcher_stats(),
        pattern: Pattern::PublishSubscribe {
            payload: fixed::<MatcherStats>(),
            user_header: None,
            qos: stats_qos(settings),
            publisher: None,
            event: None,
        },
    });
    let decision = names.decision();
    let decision_event = ServiceNames::event_of(&decision);
    services.push(ServiceSpec {
        role: "decision",
        name: decision,
        pattern: Pattern::PublishSubscribe {
            payload: slice_of::<DecisionEntry>(),
            user_header: Some(fixed::<DecisionHeader>()),
            qos: decision_qos(settings),
            publisher: Some(slice_publisher_qos(settings)),
            event: Some(decision_event.clone()),
        },
    });
    services.push(event(
        "decision_event",
        decision_event,
        "the matcher, after each decision",
        "viewers",
    ));
    services
}
