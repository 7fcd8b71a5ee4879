use iceoryx2::port::server::Server;
use iceoryx2::prelude::*;

use super::error::{IpcError, iceoryx_err};
use crate::{ReferenceAnswer, ReferenceQuery};

/// The server side of the reference service.
pub type ReferenceServer = Server<ipc::Service, ReferenceQuery, (), ReferenceAnswer, ()>;

/// What one pass over the waiting requests did.
#[derive(Debug, Default)]
pub struct Served {
    /// Answers sent.
    pub sent: u64,
    /// Requests dropped unanswered (the client over its share).
    pub dropped: u64,
    /// What failed: a failed receive ends the pass, a failed send skips
    /// that request. Empty (no allocation) when nothing failed.
    pub failures: Vec<IpcError>,
}

/// A client's port, as iceoryx2 names it in each request.
pub type ClientId = u128;

/// Answers every request waiting at `server` with `answer`, given the
/// query and the id of the client port that sent it (`None`: drop the
/// request unanswered), and calls `on_sent` with each answer that went
/// out.
pub fn answer_waiting(
    server: &ReferenceServer,
    mut answer: impl FnMut(&ReferenceQuery, ClientId) -> Option<ReferenceAnswer>,
    mut on_sent: impl FnMut(&ReferenceAnswer),
) -> Served {
    let mut served = Served::default();
    loop {
        let request = match server.receive() {
            Ok(Some(request)) => request,
            Ok(None) => break,
            Err(e) => {
                served.failures.push(iceoryx_err("receiving a request", e));
                break;
            }
        };
        let Some(reply) = answer(request.payload(), request.header().client_id().value()) else {
            served.dropped += 1;
            continue;
        };
        let sent = request
            .loan_uninit()
            .map_err(|e| iceoryx_err("loaning an answer", e))
            .map(|r| r.write_payload(reply))
            .and_then(|r| r.send().map_err(|e| iceoryx_err("sending an answer", e)));
        match sent {
            Ok(()) => {
                served.sent += 1;
                on_sent(&reply);
            }
            Err(e) => served.failures.push(e),
        }
    }
    served
}
