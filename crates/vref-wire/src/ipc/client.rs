use std::time::{Duration, Instant};

use iceoryx2::port::client::Client;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::prelude::*;

use super::error::{IpcError, iceoryx_err};
use super::{
    IpcSettings, Node, create_node, open_answer_event, open_reference, open_request_event,
};
use crate::{QueryKind, ReferenceAnswer, ReferenceQuery, SCHEMA_VERSION};

/// Longest single sleep while waiting for an answer: the pending response
/// is re-checked at least this often, whatever the events say.
const POLL: Duration = Duration::from_millis(20);

/// Asks the matcher which robot object a person means. One per thread.
pub struct ReferenceClient {
    // Ports before the node: fields drop in order, the node last.
    client: Client<ipc::Service, ReferenceQuery, (), ReferenceAnswer, ()>,
    request_event: Notifier<ipc::Service>,
    answer_event: Listener<ipc::Service>,
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
    /// node. The matcher need not be running yet.
    pub fn connect(settings: &IpcSettings, name: &str) -> Result<Self, IpcError> {
        let node = create_node(settings, name)?;
        let client = open_reference(&node, settings)?
            .client_builder()
            .create()
            .map_err(|e| iceoryx_err("creating reference client", e))?;
        let request_event = open_request_event(&node, settings)?
            .notifier_builder()
            .create()
            .map_err(|e| iceoryx_err("creating request notifier", e))?;
        let answer_event = open_answer_event(&node, settings)?
            .listener_builder()
            .create()
            .map_err(|e| iceoryx_err("creating answer listener", e))?;
        Ok(Self {
            client,
            request_event,
            answer_event,
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
        self.ask(
            query(QueryKind::HumanObject, id, [0.0; 3], [0.0; 3], 0.0),
            timeout,
        )
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
            query(QueryKind::Ray, 0, origin, direction, cone_half_angle),
            timeout,
        )
    }

    /// Which robot object does the latest gesture point at?
    pub fn latest_gesture(&mut self, timeout: Duration) -> Result<ReferenceAnswer, IpcError> {
        self.ask(
            query(QueryKind::LatestGesture, 0, [0.0; 3], [0.0; 3], 0.0),
            timeout,
        )
    }

    /// Sends `query` (its request id is set here) and waits up to
    /// `timeout` for the answer.
    pub fn ask(
        &mut self,
        mut query: ReferenceQuery,
        timeout: Duration,
    ) -> Result<ReferenceAnswer, IpcError> {
        let deadline = Instant::now() + timeout;
        query.request_id = self.next_request;
        self.next_request += 1;
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
        loop {
            if let Some(response) = pending
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
            let now = Instant::now();
            if now >= deadline {
                // A matcher that died leaves its server registered until
                // someone cleans up; do it so a restarted one is reached.
                self.node.try_cleanup_dead_nodes();
                return Err(IpcError::Timeout {
                    timeout_ms: u64::try_from(timeout.as_millis()).unwrap_or(u64::MAX),
                });
            }
            self.answer_event
                .timed_wait(|_| {}, (deadline - now).min(POLL))
                .map_err(|e| iceoryx_err("waiting for an answer", e))?;
        }
    }
}

fn query(
    kind: QueryKind,
    id: u64,
    origin: [f32; 3],
    direction: [f32; 3],
    cone: f32,
) -> ReferenceQuery {
    ReferenceQuery {
        request_id: 0,
        human_object_id: id,
        ray_origin: origin,
        ray_direction: direction,
        cone_half_angle: cone,
        kind: kind as u32,
        schema_version: SCHEMA_VERSION,
        reserved: 0,
    }
}
