use vref_config::{EndpointError, PrefixError};
use vref_wire::ipc::IpcError;

/// Why a network payload could not be decoded into a wire message, or a
/// message encoded. Decoding only: whether a decoded message makes sense
/// is vref-wire's validation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CodecError {
    #[error("encoding `{found}`, expected `{json}` or `{binary}`")]
    Encoding {
        found: String,
        json: &'static str,
        binary: String,
    },
    #[error("{what}: {bytes} bytes, expected {expected}")]
    Size {
        what: &'static str,
        bytes: usize,
        expected: String,
    },
    #[error("snapshot header counts {count} objects, the payload carries {carried}")]
    Count { count: u32, carried: usize },
    #[error("JSON {what}: {message}")]
    Json { what: &'static str, message: String },
    #[error("frame name of {len} bytes exceeds the wire's {max}")]
    FrameNameTooLong { len: usize, max: usize },
    #[error("object {id}: feature of {len} values, the first object's has {first}")]
    FeatureLengths { id: u64, len: usize, first: usize },
    #[error("unknown answer status `{0}`")]
    Status(String),
    #[error("unknown refusal `{0}` (not one of the matcher's reject reasons)")]
    Refusal(String),
    #[error("{what} of {len} entries exceeds the wire's {max}")]
    TooMany {
        what: &'static str,
        len: usize,
        max: usize,
    },
}

/// Why the Zenoh side failed: opening a session, declaring, asking.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NetError {
    #[error("Zenoh configuration `{key}`: {message}")]
    Config { key: String, message: String },
    #[error("Zenoh configuration `endpoint`: `{endpoint}`: {reason}")]
    Endpoint {
        endpoint: String,
        reason: EndpointError,
    },
    #[error("key prefix `{prefix}`: {reason}")]
    Prefix { prefix: String, reason: PrefixError },
    #[error("{what}: {message}")]
    Zenoh { what: String, message: String },
    #[error(
        "no reply from {key} within {timeout_ms} ms (is a vref-bridge with this prefix reachable?)"
    )]
    NoReply { key: String, timeout_ms: u64 },
    #[error("{key} refused: {message}")]
    Refused { key: String, message: String },
    #[error("the reply from {key}: {source}")]
    Reply {
        key: String,
        #[source]
        source: CodecError,
    },
}

/// Why the bridge could not start or stopped running.
#[derive(Debug, thiserror::Error)]
pub enum BridgeError {
    /// `[bridge]` cannot be used as given: its prefix, or the Zenoh
    /// configuration made from it.
    #[error("[bridge]")]
    Config(#[source] NetError),
    /// Zenoh failed: opening the session, declaring, receiving, closing.
    #[error(transparent)]
    Net(#[from] NetError),
    #[error("creating the iceoryx2 node")]
    Node(#[source] IpcError),
    /// A node or service of iceoryx2 could not be made or opened.
    #[error(transparent)]
    Ipc(#[from] IpcError),
    /// A port of an opened service could not be made.
    #[error("creating the {what}: {detail}")]
    Port { what: &'static str, detail: String },
    #[error("starting the {name} thread")]
    Spawn {
        name: &'static str,
        #[source]
        source: std::io::Error,
    },
    /// A thread ended while the bridge was running.
    #[error("the {name} thread stopped")]
    Stopped { name: &'static str },
    #[error("the {name} thread panicked")]
    Panicked { name: &'static str },
    /// A thread ended with an error.
    #[error("the {name} thread")]
    Thread {
        name: &'static str,
        #[source]
        source: Box<BridgeError>,
    },
}

/// Only `[bridge]` is the caller's fault (exit code 2); the rest broke
/// while running.
impl vref_logging::exit::Fault for BridgeError {
    fn is_bad_input(&self) -> bool {
        matches!(self, Self::Config(_))
    }
}

/// Shorthand for Zenoh's boxed errors, which carry only their text.
pub(crate) fn zenoh_err(what: impl Into<String>, error: impl std::fmt::Display) -> NetError {
    NetError::Zenoh {
        what: what.into(),
        message: without_location(&error.to_string()).to_owned(),
    }
}

/// Zenoh's message without the source location it appends (" at
/// /path/to/zenoh/src/file.rs:447."), which names Zenoh's code, not the
/// user's problem.
fn without_location(message: &str) -> &str {
    match message.rfind(" at /") {
        Some(k) if message[k..].contains(".rs:") => message[..k].trim_end(),
        _ => message,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zenoh_source_locations_are_cut_and_other_text_kept() {
        let e = zenoh_err(
            "connecting",
            "Unable to connect to any of [Single(tcp/127.0.0.1:1)]!  at /root/.cargo/registry/src/zenoh-1.10.2/src/net/runtime/orchestrator.rs:447.",
        );
        assert_eq!(
            e.to_string(),
            "connecting: Unable to connect to any of [Single(tcp/127.0.0.1:1)]!"
        );
        let plain = zenoh_err("declaring", "key expression at /a/b is invalid");
        assert_eq!(
            plain.to_string(),
            "declaring: key expression at /a/b is invalid"
        );
    }
}
