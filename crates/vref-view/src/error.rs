use std::path::PathBuf;

use vref_wire::ipc::IpcError;

/// Why the viewer could not start or stopped early.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    #[error(transparent)]
    Ipc(#[from] IpcError),
    #[error("{what}: {message}")]
    Iceoryx { what: &'static str, message: String },
    #[error("Foxglove SDK: {what}")]
    Foxglove {
        what: String,
        #[source]
        source: foxglove::FoxgloveError,
    },
    #[error("creating {path}")]
    Create {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl ViewError {
    pub(crate) fn iceoryx(what: &'static str) -> impl FnOnce(&dyn std::fmt::Debug) -> Self {
        move |e| ViewError::Iceoryx {
            what,
            message: format!("{e:?}"),
        }
    }

    pub(crate) fn foxglove(
        what: impl Into<String>,
    ) -> impl FnOnce(foxglove::FoxgloveError) -> Self {
        let what = what.into();
        move |source| ViewError::Foxglove { what, source }
    }
}
