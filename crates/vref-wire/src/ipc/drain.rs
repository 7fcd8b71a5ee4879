//! Emptying a subscriber's queue: every reader of vref either wants only
//! the newest sample (latest-wins feeds) or must see each one (rays,
//! decisions, recordings), and both go through here so that a receive
//! error is always handed to the caller, never lost inside a loop.

use std::fmt::Debug;

use iceoryx2::port::ReceiveError;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use iceoryx2::sample::Sample;
use iceoryx2::service::Service;

/// A subscriber of either payload kind. iceoryx2 implements `receive`
/// separately for sized and slice (`[T]`) payloads, so one generic
/// function cannot call it without this.
pub trait Receive {
    /// What one `receive` returns.
    type Sample;

    /// The next waiting sample, `None` once the queue is empty.
    fn receive_next(&self) -> Result<Option<Self::Sample>, ReceiveError>;
}

impl<S: Service, P: Debug + ZeroCopySend, H: Debug + ZeroCopySend> Receive for Subscriber<S, P, H> {
    type Sample = Sample<S, P, H>;

    fn receive_next(&self) -> Result<Option<Self::Sample>, ReceiveError> {
        self.receive()
    }
}

impl<S: Service, P: Debug + ZeroCopySend, H: Debug + ZeroCopySend> Receive
    for Subscriber<S, [P], H>
{
    type Sample = Sample<S, [P], H>;

    fn receive_next(&self) -> Result<Option<Self::Sample>, ReceiveError> {
        self.receive()
    }
}

/// What [`newest`] found.
#[derive(Debug)]
#[must_use = "a drain can end on an error, which `error` holds"]
pub struct Drained<T> {
    /// The newest sample received, if any.
    pub newest: Option<T>,
    /// How many older samples were passed over for it.
    pub skipped: u64,
    /// The error that ended the drain early, if one did: `newest` is then
    /// the newest sample before it.
    pub error: Option<ReceiveError>,
}

impl<T> Drained<T> {
    /// The newest sample, or the error if the drain ended on one (the
    /// sample received before it is dropped then).
    pub fn into_result(self) -> Result<Option<T>, ReceiveError> {
        match self.error {
            Some(e) => Err(e),
            None => Ok(self.newest),
        }
    }
}

/// Receives until the queue is empty (or a receive fails) and keeps only
/// the newest sample; each older one is released as soon as the next
/// arrives, so at most two are borrowed at a time.
pub fn newest<R: Receive + ?Sized>(subscriber: &R) -> Drained<R::Sample> {
    let mut drained = Drained {
        newest: None,
        skipped: 0,
        error: None,
    };
    loop {
        match subscriber.receive_next() {
            Ok(Some(sample)) => {
                if drained.newest.replace(sample).is_some() {
                    drained.skipped += 1;
                }
            }
            Ok(None) => return drained,
            Err(e) => {
                drained.error = Some(e);
                return drained;
            }
        }
    }
}

/// Hands every waiting sample, oldest first, to `visit` until the queue
/// is empty; returns how many. A failed receive ends the drain with its
/// error, after the samples received before it were visited.
pub fn each<R: Receive + ?Sized>(
    subscriber: &R,
    mut visit: impl FnMut(R::Sample),
) -> Result<u64, ReceiveError> {
    let mut count = 0;
    while let Some(sample) = subscriber.receive_next()? {
        visit(sample);
        count += 1;
    }
    Ok(count)
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::expect_used)]
mod tests {
    use super::*;
    use crate::ipc::{IpcSettings, create_node};

    /// A node of its own under a fresh root path and prefix, so that no
    /// other test or running service shares its services.
    fn node(root: &tempfile::TempDir, tag: &str) -> Node<ipc::Service> {
        let settings = IpcSettings {
            root_path: Some(root.path().to_owned()),
            prefix: format!("vref_drain_{tag}_{}_", std::process::id()),
            ..IpcSettings::default()
        };
        create_node(&settings, "drain-test").unwrap()
    }

    fn sized(
        node: &Node<ipc::Service>,
        name: &str,
    ) -> (
        iceoryx2::port::publisher::Publisher<ipc::Service, u64, ()>,
        Subscriber<ipc::Service, u64, ()>,
    ) {
        let service = node
            .service_builder(&name.try_into().unwrap())
            .publish_subscribe::<u64>()
            .subscriber_max_buffer_size(4)
            .open_or_create()
            .unwrap();
        let publisher = service.publisher_builder().create().unwrap();
        let subscriber = service.subscriber_builder().create().unwrap();
        (publisher, subscriber)
    }

    #[test]
    fn newest_of_three_skips_two() {
        let root = tempfile::tempdir().unwrap();
        let node = node(&root, "newest");
        let (publisher, subscriber) = sized(&node, "vref/test/drain/newest");
        for value in [1u64, 2, 3] {
            publisher.send_copy(value).unwrap();
        }
        let drained = newest(&subscriber);
        assert!(drained.error.is_none());
        assert_eq!(drained.skipped, 2);
        assert_eq!(drained.newest.map(|s| *s.payload()), Some(3));
        // The queue is empty now.
        assert!(newest(&subscriber).into_result().unwrap().is_none());
    }

    #[test]
    fn nothing_waiting_is_none() {
        let root = tempfile::tempdir().unwrap();
        let node = node(&root, "none");
        let (_publisher, subscriber) = sized(&node, "vref/test/drain/none");
        let drained = newest(&subscriber);
        assert!(drained.error.is_none());
        assert_eq!(drained.skipped, 0);
        assert!(drained.newest.is_none());
        assert_eq!(each(&subscriber, |_| {}).unwrap(), 0);
    }

    #[test]
    fn each_visits_every_sample_in_order() {
        let root = tempfile::tempdir().unwrap();
        let node = node(&root, "each");
        let (publisher, subscriber) = sized(&node, "vref/test/drain/each");
        for value in [7u64, 8, 9] {
            publisher.send_copy(value).unwrap();
        }
        let mut seen = Vec::new();
        let count = each(&subscriber, |s| seen.push(*s.payload())).unwrap();
        assert_eq!(count, 3);
        assert_eq!(seen, [7, 8, 9]);
    }

    #[test]
    fn slice_payloads_drain_too() {
        let root = tempfile::tempdir().unwrap();
        let node = node(&root, "slice");
        let service = node
            .service_builder(&"vref/test/drain/slice".try_into().unwrap())
            .publish_subscribe::<[u32]>()
            .user_header::<u64>()
            .subscriber_max_buffer_size(4)
            .open_or_create()
            .unwrap();
        let publisher = service
            .publisher_builder()
            .initial_max_slice_len(4)
            .create()
            .unwrap();
        let subscriber = service.subscriber_builder().create().unwrap();
        for n in 1..=3u32 {
            let mut sample = publisher.loan_slice_uninit(n as usize).unwrap();
            *sample.user_header_mut() = u64::from(n);
            sample.write_from_fn(|i| i as u32).send().unwrap();
        }
        let drained = newest(&subscriber);
        assert!(drained.error.is_none());
        assert_eq!(drained.skipped, 2);
        let sample = drained.newest.expect("a sample");
        assert_eq!(*sample.user_header(), 3);
        assert_eq!(sample.payload(), &[0, 1, 2]);
    }
}
