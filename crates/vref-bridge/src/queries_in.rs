//! Queries in: a Zenoh queryable at `<prefix>/reference`. One thread owns
//! the iceoryx2 client and asks the local matcher for each query that
//! passes the intake, then replies in the query's own encoding; a refused
//! query, or one the matcher did not answer, gets an error reply saying
//! why.

use std::sync::Arc;
use std::time::{Duration, Instant};

use vref_wire::ReferenceAnswer;
use vref_wire::ipc::ReferenceClient;
use zenoh::Wait;
use zenoh::query::Query;

use crate::error::zenoh_err;
use crate::format::{Format, Message};
use crate::net::ErrorReply;
use crate::shared::{POLL, Shared, lock};
use crate::workers::Worker;
use crate::{BridgeError, binary, json};

/// The counter of queries that passed the checks but got no answer from
/// the matcher (not running, or too slow).
const NO_ANSWER: &str = "no_answer";

/// Declares the queryable and starts the thread that answers it.
pub(crate) fn start(session: &zenoh::Session, shared: &Arc<Shared>) -> Result<Worker, BridgeError> {
    let key = shared.keys.reference();
    let queryable = session
        .declare_queryable(&key)
        .complete(true)
        .wait()
        .map_err(|e| zenoh_err(format!("declaring the queryable {key}"), e))?;
    let shared = Arc::clone(shared);
    std::thread::Builder::new()
        .name("queries-in".to_owned())
        .spawn(move || {
            let name = format!("vref-bridge-queries-{}", std::process::id());
            let mut client = ReferenceClient::connect(&shared.config.ipc, &name)?;
            let timeout = Duration::from_millis(shared.config.bridge.query_timeout_ms);
            while !shared.stopping() {
                match queryable.recv_timeout(POLL) {
                    Ok(Some(query)) => answer(&shared, &mut client, &query, timeout),
                    Ok(None) => {}
                    Err(e) => return Err(zenoh_err("receiving queries", e).into()),
                }
            }
            Ok(())
        })
        .map_err(|source| BridgeError::Spawn {
            name: "queries",
            source,
        })
}

fn answer(shared: &Shared, client: &mut ReferenceClient, query: &Query, timeout: Duration) {
    let encoding = query.encoding().map(ToString::to_string);
    let payload = query.payload().map(|p| p.to_bytes());
    let checked =
        lock(&shared.queries).query(encoding.as_deref(), payload.as_deref(), Instant::now());
    let (remote, format) = match checked {
        Ok(checked) => checked,
        Err(refusal) => {
            tracing::debug!(reason = refusal.name(), "refused query: {refusal}");
            return refuse(query, &refusal.to_string(), refusal.name());
        }
    };
    let answer = match client.ask(remote, timeout) {
        Ok(answer) => answer,
        Err(e) => {
            lock(&shared.queries).counters_mut().refuse(NO_ANSWER);
            tracing::warn!("asking the matcher: {e}");
            return refuse(
                query,
                &format!("the matcher did not answer: {e}"),
                NO_ANSWER,
            );
        }
    };
    let bytes = encode_reply(answer, remote.request_id, format);
    let sent = query
        .reply(shared.keys.reference(), bytes)
        .encoding(Message::Answer.encoding(format))
        .express(true)
        .wait();
    if let Err(e) = sent {
        lock(&shared.published).failed += 1;
        tracing::warn!("replying to a query: {e}");
    }
}

/// The matcher's answer to a remote query, in the query's encoding.
fn encode_reply(mut answer: ReferenceAnswer, remote_request: u64, format: Format) -> Vec<u8> {
    // The client numbered its own request; the remote one is echoed.
    answer.request_id = remote_request;
    match format {
        Format::Json => json::encode_answer(&answer),
        Format::Binary => binary::encode_answer(&answer),
    }
}

fn refuse(query: &Query, error: &str, reason: &str) {
    let reply = ErrorReply {
        error: error.to_owned(),
        reason: reason.to_owned(),
    };
    if let Err(e) = query
        .reply_err(reply.to_json())
        .encoding(ErrorReply::ENCODING)
        .wait()
    {
        tracing::warn!("replying to a query: {e}");
    }
}

#[cfg(test)]
mod tests {
    use vref_wire::AnswerStatus;

    use super::*;

    #[test]
    fn replies_echo_the_remote_request_in_its_encoding() {
        let mut answer = ReferenceAnswer::empty(9, AnswerStatus::Ok);
        answer.robot_track_id = 42;
        for format in [Format::Json, Format::Binary] {
            let bytes = encode_reply(answer, 1234, format);
            let back = match format {
                Format::Json => json::decode_answer(&bytes),
                Format::Binary => binary::decode_answer(&bytes),
            }
            .unwrap_or_else(|e| panic!("{format:?}: {e}"));
            assert_eq!(back.request_id, 1234, "{format:?}");
            assert_eq!(back.robot_track_id, 42, "{format:?}");
        }
    }
}
