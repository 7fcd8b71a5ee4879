//! A queryable that answers every reference query at once, with no matcher
//! behind it: Zenoh's own round trip on this machine, the floor under what
//! the bridge adds (`vref bench remote` measures it in the same run).
//!
//! It receives as the bridge does (Zenoh's FIFO channel, read by a thread of
//! its own) and replies as the bridge does (the query's encoding, express),
//! so the difference between the bridge's round trip and this one is the
//! bridge's own work: the intake's checks and the local iceoryx2 question.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use vref_config::ZenohMode;
use vref_wire::{AnswerStatus, ReferenceAnswer};
use zenoh::Wait;
use zenoh::query::Query;

use crate::error::zenoh_err;
use crate::format::{Format, Message};
use crate::keys::Keys;
use crate::net::zenoh_config;
use crate::{NetError, binary, json};

/// Longest the echo thread waits before looking at its stop flag.
const POLL: Duration = Duration::from_millis(100);

/// The running echo; it stops when dropped.
pub struct Echo {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
    session: Option<zenoh::Session>,
}

impl std::fmt::Debug for Echo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Echo").finish_non_exhaustive()
    }
}

impl Echo {
    /// A peer session listening on `endpoint` that answers reference
    /// queries under `prefix`, as a bridge there would.
    pub fn start(endpoint: &str, prefix: &str) -> Result<Self, NetError> {
        let key = Keys::new(prefix)?.reference();
        let config = zenoh_config(ZenohMode::Peer, &[endpoint.to_owned()], &[], false)?;
        let session = zenoh::open(config)
            .wait()
            .map_err(|e| zenoh_err(format!("opening an echo session on {endpoint}"), e))?;
        let queryable = session
            .declare_queryable(&key)
            .complete(true)
            .wait()
            .map_err(|e| zenoh_err(format!("declaring the echo queryable {key}"), e))?;
        let stop = Arc::new(AtomicBool::new(false));
        let stopping = Arc::clone(&stop);
        let thread = std::thread::Builder::new()
            .name("zenoh-echo".to_owned())
            .spawn(move || {
                while !stopping.load(Ordering::Relaxed) {
                    match queryable.recv_timeout(POLL) {
                        Ok(Some(query)) => reply(&query, &key),
                        Ok(None) => {}
                        Err(_) => return,
                    }
                }
            })
            .map_err(|e| zenoh_err("starting the echo thread", e))?;
        Ok(Self {
            stop,
            thread: Some(thread),
            session: Some(session),
        })
    }
}

/// An empty `ok` answer echoing the request id; a query that cannot be
/// read gets no reply (the asker times out, and counts it).
fn reply(query: &Query, key: &str) {
    let Some(encoding) = query.encoding().map(ToString::to_string) else {
        return;
    };
    let Some(bytes) = query.payload().map(|p| p.to_bytes()) else {
        return;
    };
    let Ok(format) = Message::Query.format_of(&encoding) else {
        return;
    };
    let decoded = match format {
        Format::Json => json::decode_query(&bytes),
        Format::Binary => binary::decode_query(&bytes),
    };
    let Ok(asked) = decoded else {
        return;
    };
    let answer = ReferenceAnswer::empty(asked.request_id, AnswerStatus::Ok);
    let payload = match format {
        Format::Json => json::encode_answer(&answer),
        Format::Binary => binary::encode_answer(&answer),
    };
    // A failed reply is the asker's timeout; nothing else to do here.
    let _ = query
        .reply(key, payload)
        .encoding(Message::Answer.encoding(format))
        .express(true)
        .wait();
}

impl Drop for Echo {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
        if let Some(session) = self.session.take() {
            let _ = session.close().wait();
        }
    }
}
