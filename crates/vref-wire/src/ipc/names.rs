use vref_scene::Side;

/// The names of vref's services under a namespace.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ServiceNames {
    namespace: String,
}

impl ServiceNames {
    pub fn new(namespace: &str) -> Self {
        Self {
            namespace: namespace.trim_end_matches('/').to_owned(),
        }
    }

    /// Snapshots of one side's view.
    pub fn snapshot(&self, side: Side) -> String {
        format!("{}/{side}/snapshot", self.namespace)
    }

    /// Pointing rays from the gesture feed.
    pub fn gesture(&self) -> String {
        format!("{}/human/gesture", self.namespace)
    }

    /// Reference queries and answers (request/response).
    pub fn reference(&self) -> String {
        format!("{}/reference", self.namespace)
    }

    /// The event paired with a data service, so a WaitSet can wake on it.
    pub fn event_of(data_service: &str) -> String {
        format!("{data_service}/event")
    }

    /// The matcher's periodic statistics.
    pub fn matcher_stats(&self) -> String {
        format!("{}/matcher/stats", self.namespace)
    }

    /// The matcher's latest decision: every human object's outcome.
    pub fn decision(&self) -> String {
        format!("{}/matcher/decision", self.namespace)
    }

    /// Signalled by the matcher after it sent answers.
    pub fn answers(&self) -> String {
        format!("{}/reference/answers", self.namespace)
    }
}
