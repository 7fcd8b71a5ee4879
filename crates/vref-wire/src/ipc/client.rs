use std::time::{Duration, Instant};

use iceoryx2::node::NodeView;
use iceoryx2::pending_response::PendingResponse;
use iceoryx2::port::client::Client;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::prelude::*;
use iceoryx2::service::dynamic_config::request_response::ServerDetails;

use super::error::{IpcError, iceoryx_err};
use super::{
    IpcSettings, Node, ReferencePort, create_node, listener_timeout, open_answer_event,
    open_reference, open_request_event,
};
use crate::{ReferenceAnswer, ReferenceQuery};

/// Longest single sleep while waiting for an answer: the pending response
/// is re-checked at least this often, whatever the events say.
const POLL: Duration = Duration::from_millis(20);
/// While an answer is late, how often the client looks whether the
/// servers changed (a matcher gone or started). It does not clean up dead
/// nodes meanwhile: iceoryx2's cleanup of a killed matcher blocks for as
/// long as it takes (over a second on a loaded machine, past the query's
/// deadline), and a restarted matcher cleans up before it serves.
const CHECK_EVERY: Duration = Duration::from_millis(20);
/// How long a request must stay let go, with the same servers there, to
/// count as refused: a dead server's cleanup drops its connection a moment
/// before its listing.
const REFUSED_AFTER: Duration = Duration::from_millis(100);
/// Servers a reference service allows (services.rs), and so the most a
/// client can see.
const MAX_SERVERS: usize = 8;

/// The servers connected to the reference service, by port id: a fixed
/// array, so that comparing them allocates nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Servers {
    ids: [u128; MAX_SERVERS],
    count: usize,
}

impl Servers {
    fn of(port: &ReferencePort) -> Self {
        let mut servers = Self::listed(port, |details| details.server_id.value());
        servers.ids[..servers.count].sort_unstable();
        servers
    }

    /// One id per listed server, as `id` reads it from its details.
    fn listed(port: &ReferencePort, id: impl Fn(&ServerDetails) -> u128) -> Self {
        let mut servers = Self {
            ids: [0; MAX_SERVERS],
            count: 0,
        };
        port.dynamic_config().list_servers(|details| {
            if servers.count < MAX_SERVERS {
                servers.ids[servers.count] = id(details);
                servers.count += 1;
            }
            CallbackProgression::Continue
        });
        servers
    }

    fn is_empty(&self) -> bool {
        self.count == 0
    }
}

/// The servers of the reference service, and how many of them belong to
/// a live node; `None` when the nodes cannot be listed. A killed
/// matcher's server stays listed until someone cleans up after it, so the
/// listing alone does not say whether a matcher runs. Reads every node's
/// files (without the cleanup's blocking): only asked when an error is
/// about to be reported.
fn live_servers(port: &ReferencePort, node: &Node) -> Option<(usize, usize)> {
    let nodes = Servers::listed(port, |details| details.node_id.value());
    let mut alive = 0;
    Node::list(node.config(), |state| {
        if let NodeState::Alive(view) = &state
            && nodes.ids[..nodes.count].contains(&view.id().value())
        {
            alive += 1;
        }
        CallbackProgression::Continue
    })
    .ok()
    .map(|_| (nodes.count, alive))
}

/// Whether every server of the reference service belongs to a live node.
/// A killed matcher's cleanup lets its requests go before its server
/// leaves the listing: on a loaded machine the gap between the two
/// outlasts [`REFUSED_AFTER`], and a request let go by a dead server is no
/// refusal. Unable to tell: what the requests say stands.
fn servers_alive(port: &ReferencePort, node: &Node) -> bool {
    live_servers(port, node).is_none_or(|(listed, alive)| alive == listed)
}

/// Whether no server of the reference service belongs to a live node (none
/// listed, or only killed matchers' not yet cleaned up).
fn no_live_server(port: &ReferencePort, node: &Node) -> bool {
    match live_servers(port, node) {
        Some((_, alive)) => alive == 0,
        None => Servers::of(port).is_empty(),
    }
}

/// Asks the matcher which robot object a person means. One per thread.
pub struct ReferenceClient {
    // Ports before the node: fields drop in order, the node last.
    client: Client<ipc::Service, ReferenceQuery, (), ReferenceAnswer, ()>,
    request_event: Notifier<ipc::Service>,
    answer_event: Listener<ipc::Service>,
    port: ReferencePort,
    node: Node,
    next_request: u64,
}

impl std::fmt::Debug for ReferenceClient {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ReferenceClient")
            .field("next_request", &self.next_request)
            .finish_non_exhaustive()
    }
}

impl ReferenceClient {
    /// Connects under the settings' namespace; `name` names this client's
    /// node. The matcher need not be running yet. Past `[ipc] max_clients`
    /// controllers the error says so ([`IpcError::TooManyClients`]).
    pub fn connect(settings: &IpcSettings, name: &str) -> Result<Self, IpcError> {
        let node = create_node(settings, name)?;
        // A controller killed without cleanup holds a client's place.
        node.try_cleanup_dead_nodes();
        let full = |what: &'static str| {
            move |e: &dyn std::fmt::Debug| {
                let text = format!("{e:?}");
                if text.contains("ExceedsMaxSupported") {
                    IpcError::TooManyClients {
                        limit: settings.max_clients,
                    }
                } else {
                    iceoryx_err(what, text)
                }
            }
        };
        let port = open_reference(&node, settings)?;
        let client = port
            .client_builder()
            .create()
            .map_err(|e| full("creating reference client")(&e))?;
        let request_event = open_request_event(&node, settings)?
            .notifier_builder()
            .create()
            .map_err(|e| full("creating request notifier")(&e))?;
        let answer_event = open_answer_event(&node, settings)?
            .listener_builder()
            .create()
            .map_err(|e| full("creating answer listener")(&e))?;
        Ok(Self {
            client,
            request_event,
            answer_event,
            port,
            node,
            next_request: 1,
        })
    }

    /// Which robot object is human object `id`?
    pub fn by_human_object(
        &mut self,
        id: u64,
        timeout: Duration,
    ) -> Result<ReferenceAnswer, IpcError> {
        self.ask(ReferenceQuery::human_object(id), timeout)
    }

    /// Which robot object does this ray (human view frame) point at?
    pub fn by_ray(
        &mut self,
        origin: [f32; 3],
        direction: [f32; 3],
        cone_half_angle: f32,
        timeout: Duration,
    ) -> Result<ReferenceAnswer, IpcError> {
        self.ask(
            ReferenceQuery::ray(origin, direction, cone_half_angle),
            timeout,
        )
    }

    /// Which robot object does the latest gesture point at?
    pub fn latest_gesture(&mut self, timeout: Duration) -> Result<ReferenceAnswer, IpcError> {
        self.ask(ReferenceQuery::latest_gesture(), timeout)
    }

    /// Sends `query` (its request id is set here) and waits up to
    /// `timeout` for the answer. A matcher that leaves or starts meanwhile
    /// (a restart, or the first start) is sent the query again, so that
    /// the one serving gets it.
    pub fn ask(
        &mut self,
        mut query: ReferenceQuery,
        timeout: Duration,
    ) -> Result<ReferenceAnswer, IpcError> {
        let start = Instant::now();
        let deadline = start + timeout;
        query.request_id = self.next_request;
        self.next_request += 1;
        let mut servers = Servers::of(&self.port);
        let mut pending = Some(self.send(query)?);
        let mut checked = start;
        let mut let_go_since: Option<Instant> = None;
        loop {
            let now = Instant::now();
            if let Some(sent) = &pending {
                // Read before the answer: a server answers, then lets go.
                let connected = sent.is_connected();
                if let Some(response) = sent
                    .receive()
                    .map_err(|e| iceoryx_err("receiving an answer", e))?
                {
                    let answer = *response.payload();
                    if answer.request_id != query.request_id {
                        return Err(IpcError::WrongAnswer {
                            expected: query.request_id,
                            got: answer.request_id,
                        });
                    }
                    return Ok(answer);
                }
                let let_go = !connected
                    && sent.number_of_server_connections() > 0
                    && Servers::of(&self.port) == servers;
                if !let_go {
                    let_go_since = None;
                } else if now.duration_since(*let_go_since.get_or_insert(now)) >= REFUSED_AFTER {
                    if servers_alive(&self.port, &self.node) {
                        // Every server it reached let it go unanswered.
                        return Err(IpcError::Refused);
                    }
                    // A dead one's cleanup is under way: the servers
                    // change once it ends, and the query is sent again.
                    let_go_since = None;
                }
            }
            if now >= deadline {
                let timeout_ms = u64::try_from(timeout.as_millis()).unwrap_or(u64::MAX);
                return Err(if no_live_server(&self.port, &self.node) {
                    IpcError::NoServer { timeout_ms }
                } else {
                    IpcError::Timeout { timeout_ms }
                });
            }
            if now.duration_since(checked) >= CHECK_EVERY {
                checked = now;
                let current = Servers::of(&self.port);
                if current != servers {
                    servers = current;
                    // Its place among the client's active requests first.
                    pending = None;
                    let_go_since = None;
                    if !servers.is_empty() {
                        pending = Some(self.send(query)?);
                    }
                    continue;
                }
            }
            self.answer_event
                .timed_wait(|_| {}, listener_timeout((deadline - now).min(POLL)))
                .map_err(|e| iceoryx_err("waiting for an answer", e))?;
        }
    }

    fn send(&self, query: ReferenceQuery) -> Result<Pending, IpcError> {
        let pending = self
            .client
            .loan_uninit()
            .map_err(|e| iceoryx_err("loaning a request", e))?
            .write_payload(query)
            .send()
            .map_err(|e| iceoryx_err("sending a request", e))?;
        self.request_event
            .notify()
            .map_err(|e| iceoryx_err("notifying a request", e))?;
        Ok(pending)
    }
}

type Pending = PendingResponse<ipc::Service, ReferenceQuery, (), ReferenceAnswer, ()>;
