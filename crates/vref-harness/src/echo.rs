//! The echo server of `vref bench query`: answers every reference query
//! at once with an empty answer carrying its request id, on its own
//! namespace below the configured one, with the matcher's wake-ups
//! (request event in a WaitSet, answer event after sending). It runs as a
//! process of its own (`vref bench echo-server`), like the matcher, so
//! that the bare iceoryx2 round trip is measured as the matcher's is.

use iceoryx2::prelude::*;
use iceoryx2::waitset::WaitSetRunResult;
use vref_wire::ipc::{
    IpcError, IpcSettings, answer_waiting, create_node, open_answer_event, open_reference,
    open_request_event,
};
use vref_wire::{AnswerStatus, ReferenceAnswer, ReferenceQuery};

/// Why the echo server could not serve.
#[derive(Debug, thiserror::Error)]
pub enum EchoError {
    #[error(transparent)]
    Ipc(#[from] IpcError),
    #[error("{what}: {message}")]
    Iceoryx { what: &'static str, message: String },
}

fn iceoryx(what: &'static str) -> impl FnOnce(&dyn std::fmt::Debug) -> EchoError {
    move |e| EchoError::Iceoryx {
        what,
        message: format!("{e:?}"),
    }
}

/// The echo server's services live under this namespace below the
/// configured one, so they never meet the matcher's.
pub fn echo_settings(ipc: &IpcSettings) -> IpcSettings {
    let mut echo = ipc.clone();
    echo.namespace = format!("{}/bench-echo", ipc.namespace.trim_end_matches('/'));
    echo
}

/// Serves on `ipc` (already the echo's settings, [`echo_settings`]) until
/// SIGINT or SIGTERM; how many queries it answered.
pub fn serve(ipc: &IpcSettings) -> Result<u64, EchoError> {
    let node = create_node(ipc, "vref-bench-echo")?;
    node.try_cleanup_dead_nodes();
    let server = open_reference(&node, ipc)?
        .server_builder()
        .create()
        .map_err(|e| iceoryx("creating the echo server")(&e))?;
    let requests = open_request_event(&node, ipc)?
        .listener_builder()
        .create()
        .map_err(|e| iceoryx("creating the request listener")(&e))?;
    let answers = open_answer_event(&node, ipc)?
        .notifier_builder()
        .create()
        .map_err(|e| iceoryx("creating the answer notifier")(&e))?;
    let waitset = WaitSetBuilder::new()
        .create::<ipc::Service>()
        .map_err(|e| iceoryx("creating the WaitSet")(&e))?;
    let _guard = waitset
        .attach_notification(&requests)
        .map_err(|e| iceoryx("attaching to the WaitSet")(&e))?;
    tracing::info!(namespace = %ipc.namespace, "echo server ready");
    let mut served = 0u64;
    let mut on_event = |_: WaitSetAttachmentId<ipc::Service>| {
        if let Err(e) = requests.try_wait(|_| {}) {
            tracing::warn!("draining the request listener: {e:?}");
        }
        let done = answer_waiting(&server, |q, _| Some(echo(q)), |_| {});
        for failure in &done.failures {
            tracing::warn!("{failure}");
        }
        served += done.sent;
        if done.sent > 0
            && let Err(e) = answers.notify()
        {
            tracing::warn!("notifying answers: {e:?}");
        }
        CallbackProgression::Continue
    };
    let result = loop {
        match waitset.wait_and_process(&mut on_event) {
            Ok(WaitSetRunResult::Interrupt) => continue,
            other => break other.map_err(|e| iceoryx("waiting")(&e))?,
        }
    };
    tracing::info!(?result, served, "echo server stopped");
    Ok(served)
}

/// The answer the echo gives: the request back, nothing looked up.
pub fn echo(query: &ReferenceQuery) -> ReferenceAnswer {
    ReferenceAnswer {
        human_object_id: query.human_object_id,
        ..ReferenceAnswer::empty(query.request_id, AnswerStatus::NoMatch)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_echo_namespace_is_apart_from_the_matchers() {
        let ipc = IpcSettings::default();
        let echo = echo_settings(&ipc);
        assert_ne!(echo.namespace, ipc.namespace);
        assert!(echo.namespace.starts_with(&ipc.namespace));
        assert_eq!((echo.prefix, echo.root_path), (ipc.prefix, ipc.root_path));
    }
}
