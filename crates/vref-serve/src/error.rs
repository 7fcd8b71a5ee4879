//! What can stop the matcher service.

use vref_match::MatchError;
use vref_wire::ipc::IpcError;

/// Why the matcher could not start or stopped running.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The `[matcher]` or `[matching]` settings cannot make a state or a
    /// solver (a bad method or tier, parameters out of range).
    #[error("matcher configuration: {0}")]
    Config(#[from] MatchError),
    /// A node or service of iceoryx2 could not be made or opened.
    #[error(transparent)]
    Ipc(#[from] IpcError),
    /// A port of an opened service could not be made.
    #[error("creating the {what}: {detail}")]
    Port { what: &'static str, detail: String },
    /// The WaitSet could not be made, attached to, or waited on.
    #[error("{what}: {detail}")]
    WaitSet { what: &'static str, detail: String },
    /// The operating system refused the solver thread.
    #[error("starting the solver thread: {0}")]
    Thread(#[source] std::io::Error),
}

/// Only the configuration is the caller's fault (exit code 2); the rest
/// broke while running.
impl vref_logging::exit::Fault for ServeError {
    fn is_bad_input(&self) -> bool {
        matches!(self, Self::Config(_))
    }
}
