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
    #[error("key prefix `{prefix}`: {message}")]
    Prefix { prefix: String, message: String },
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

/// Shorthand for Zenoh's boxed errors, which carry only their text.
pub(crate) fn zenoh_err(what: impl Into<String>, error: impl std::fmt::Display) -> NetError {
    NetError::Zenoh {
        what: what.into(),
        message: error.to_string(),
    }
}
