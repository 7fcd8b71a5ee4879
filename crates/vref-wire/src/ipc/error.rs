/// Why an IPC operation failed. iceoryx2's own error types are many and
/// version-specific; their text is kept, with what was being done.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IpcError {
    #[error("invalid name or path `{value}` for {what}")]
    BadName { what: &'static str, value: String },
    #[error("{what}: {message}")]
    Iceoryx { what: String, message: String },
    #[error("no answer within {timeout_ms} ms, though a matcher is serving (busy or stalled)")]
    Timeout { timeout_ms: u64 },
    #[error(
        "no matcher served the request within {timeout_ms} ms (none is running under these [ipc] settings)"
    )]
    NoServer { timeout_ms: u64 },
    #[error(
        "the matcher dropped the request unanswered: this client is over [matcher] max_queries_per_client_hz"
    )]
    Refused,
    #[error(
        "the reference service already has its {limit} controllers: [ipc] max_clients = {limit} \
         (raise it in every process's configuration)"
    )]
    TooManyClients { limit: usize },
    #[error("the answer echoed request {got}, expected {expected}")]
    WrongAnswer { expected: u64, got: u64 },
    #[error("snapshot of {count} objects exceeds the wire capacity of {capacity}")]
    TooManyObjects { count: usize, capacity: usize },
}

impl IpcError {
    pub(crate) fn iceoryx(
        what: impl Into<String>,
    ) -> impl FnOnce(&dyn std::fmt::Debug) -> IpcError {
        let what = what.into();
        move |e| IpcError::Iceoryx {
            what,
            message: format!("{e:?}"),
        }
    }
}

/// Shorthand: `result.map_err(|e| iceoryx_err("what", e))`.
pub(crate) fn iceoryx_err(what: impl Into<String>, error: impl std::fmt::Debug) -> IpcError {
    IpcError::iceoryx(what)(&error)
}
