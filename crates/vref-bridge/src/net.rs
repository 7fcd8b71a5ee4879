//! Zenoh sessions from vref's settings, and the remote side of reference
//! queries: what `vref query --remote`, `vref bench remote` and any Rust
//! controller on another computer use.

use std::time::Duration;

use vref_config::{BridgeSettings, ZenohMode};
use vref_wire::{ReferenceAnswer, ReferenceQuery};
use zenoh::Wait;
use zenoh::query::{ConsolidationMode, QueryTarget};

use crate::error::zenoh_err;
use crate::format::{Format, JSON, Message};
use crate::keys::Keys;
use crate::{NetError, binary, json};

/// A Zenoh session's configuration: mode, endpoints, multicast scouting.
/// Nothing else is changed from Zenoh's defaults.
pub fn zenoh_config(
    mode: ZenohMode,
    listen: &[String],
    connect: &[String],
    multicast_scouting: bool,
) -> Result<zenoh::Config, NetError> {
    let mut config = zenoh::Config::default();
    let mut set = |key: &str, value: String| {
        config
            .insert_json5(key, &value)
            .map_err(|e| NetError::Config {
                key: key.to_owned(),
                message: e.to_string(),
            })
    };
    set("mode", format!("\"{}\"", mode.name()))?;
    set("listen/endpoints", json_list(listen))?;
    set("connect/endpoints", json_list(connect))?;
    set("scouting/multicast/enabled", multicast_scouting.to_string())?;
    Ok(config)
}

fn json_list(items: &[String]) -> String {
    serde_json::to_string(items).unwrap_or_else(|_| "[]".to_owned())
}

/// Room beside a payload in one Zenoh message: its key, encoding and
/// headers (a prefix is at most a few hundred bytes).
pub const ZENOH_OVERHEAD_BYTES: usize = 16 * 1024;

/// The bridge's own session, as `[bridge]` says. Zenoh reassembles a
/// fragmented message in full before handing it over, up to 1 GiB by
/// default: the bridge's receive limit is its `max_message_bytes` (plus
/// the message's own overhead), so a larger put is dropped by Zenoh
/// fragment by fragment instead of being buffered and refused after.
pub fn open_bridge_session(settings: &BridgeSettings) -> Result<zenoh::Session, NetError> {
    let mut config = zenoh_config(
        settings.mode,
        &settings.listen,
        &settings.connect,
        settings.multicast_scouting,
    )?;
    let key = "transport/link/rx/max_message_size";
    let limit = settings
        .max_message_bytes
        .saturating_add(ZENOH_OVERHEAD_BYTES);
    config
        .insert_json5(key, &limit.to_string())
        .map_err(|e| NetError::Config {
            key: key.to_owned(),
            message: e.to_string(),
        })?;
    zenoh::open(config)
        .wait()
        .map_err(|e| zenoh_err("opening the Zenoh session", e))
}

/// A client session to `endpoints` (a bridge in peer mode, or a router),
/// without scouting: it reaches exactly what it is told to.
pub fn open_client_session(endpoints: &[String]) -> Result<zenoh::Session, NetError> {
    let config = zenoh_config(ZenohMode::Client, &[], endpoints, false)?;
    zenoh::open(config).wait().map_err(|e| {
        zenoh_err(
            format!("connecting to {} over Zenoh", endpoints.join(", ")),
            e,
        )
    })
}

/// A peer session connected to `endpoints` that listens nowhere and does
/// not scout: a controller that talks to several robots directly.
pub fn open_peer_session(endpoints: &[String]) -> Result<zenoh::Session, NetError> {
    let config = zenoh_config(ZenohMode::Peer, &[], endpoints, false)?;
    zenoh::open(config).wait().map_err(|e| {
        zenoh_err(
            format!("connecting to {} over Zenoh", endpoints.join(", ")),
            e,
        )
    })
}

/// Asks one robot's matcher through its bridge, from anywhere on the
/// network.
pub struct RemoteClient {
    session: zenoh::Session,
    key: String,
    format: Format,
    next_request: u64,
}

impl std::fmt::Debug for RemoteClient {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RemoteClient")
            .field("key", &self.key)
            .field("format", &self.format)
            .finish_non_exhaustive()
    }
}

impl RemoteClient {
    /// A client of the robot under `prefix`, asking in `format`, on an
    /// open session (several robots can share one).
    pub fn new(session: zenoh::Session, prefix: &str, format: Format) -> Result<Self, NetError> {
        Ok(Self {
            key: Keys::new(prefix)?.reference(),
            session,
            format,
            next_request: 1,
        })
    }

    /// Connects a client session to `endpoint` first.
    pub fn connect(endpoint: &str, prefix: &str, format: Format) -> Result<Self, NetError> {
        vref_config::check_endpoint(endpoint).map_err(|reason| NetError::Endpoint {
            endpoint: endpoint.to_owned(),
            reason,
        })?;
        Self::new(open_client_session(&[endpoint.to_owned()])?, prefix, format)
    }

    /// Sends `query` (its request id is set here) and waits up to
    /// `timeout` for the answer.
    pub fn ask(
        &mut self,
        mut query: ReferenceQuery,
        timeout: Duration,
    ) -> Result<ReferenceAnswer, NetError> {
        query.request_id = self.next_request;
        self.next_request += 1;
        let payload = match self.format {
            Format::Json => json::encode_query(&query),
            Format::Binary => binary::encode_query(&query),
        };
        let replies = self
            .session
            .get(&self.key)
            .payload(payload)
            .encoding(Message::Query.encoding(self.format))
            .target(QueryTarget::BestMatching)
            // One queryable answers once: Zenoh's default (latest) would hold
            // the reply back until the query's final message.
            .consolidation(ConsolidationMode::None)
            .timeout(timeout)
            .express(true)
            .wait()
            .map_err(|e| zenoh_err(format!("querying {}", self.key), e))?;
        let no_reply = || NetError::NoReply {
            key: self.key.clone(),
            timeout_ms: u64::try_from(timeout.as_millis()).unwrap_or(u64::MAX),
        };
        // The channel closes when the query times out or every queryable
        // has replied.
        let reply = replies
            .recv_timeout(timeout)
            .map_err(|_| no_reply())?
            .ok_or_else(no_reply)?;
        let reply_error = |source| NetError::Reply {
            key: self.key.clone(),
            source,
        };
        match reply.result() {
            Ok(sample) => {
                let bytes = sample.payload().to_bytes();
                let encoding = sample.encoding().to_string();
                let answer = match Message::Answer.format_of(&encoding).map_err(reply_error)? {
                    Format::Json => json::decode_answer(&bytes),
                    Format::Binary => binary::decode_answer(&bytes),
                }
                .map_err(reply_error)?;
                if answer.request_id != query.request_id {
                    return Err(NetError::Refused {
                        key: self.key.clone(),
                        message: format!(
                            "the answer echoed request {}, expected {}",
                            answer.request_id, query.request_id
                        ),
                    });
                }
                Ok(answer)
            }
            Err(error) => Err(NetError::Refused {
                key: self.key.clone(),
                message: refusal_text(&error.payload().to_bytes()),
            }),
        }
    }
}

/// The bridge's error replies are `{"error": "..."}`; anything else is
/// shown as text.
fn refusal_text(bytes: &[u8]) -> String {
    serde_json::from_slice::<ErrorReply>(bytes)
        .map(|e| e.error)
        .unwrap_or_else(|_| String::from_utf8_lossy(bytes).into_owned())
}

/// What the bridge replies when it cannot ask the matcher.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ErrorReply {
    pub error: String,
    /// The counter the refusal went to, e.g. `malformed`.
    pub reason: String,
}

impl ErrorReply {
    pub fn to_json(&self) -> Vec<u8> {
        serde_json::to_vec(self).unwrap_or_default()
    }

    pub const ENCODING: &'static str = JSON;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configurations_carry_the_settings() {
        let config = zenoh_config(
            ZenohMode::Peer,
            &["tcp/127.0.0.1:7447".to_owned()],
            &[],
            false,
        )
        .unwrap();
        let text = format!("{config}");
        assert!(text.contains("127.0.0.1:7447"), "{text}");
        assert!(zenoh_config(ZenohMode::Client, &[], &["nonsense".to_owned()], false).is_err());
    }

    #[test]
    fn error_replies_read_back_as_their_message() {
        let reply = ErrorReply {
            error: "over the rate limit".to_owned(),
            reason: "rate_limited".to_owned(),
        };
        assert_eq!(refusal_text(&reply.to_json()), "over the rate limit");
        assert_eq!(refusal_text(b"plain"), "plain");
    }
}
