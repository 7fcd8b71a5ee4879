//! The Zenoh keys of one robot, all under its prefix (`vref/<robot>`), so
//! that several robots share a network and a headset or controller
//! addresses one by its prefix.

use crate::NetError;

/// Every key of one robot.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Keys {
    prefix: String,
}

impl Keys {
    /// `prefix` as `[bridge] prefix` allows it: no wildcards, no empty
    /// chunk, so it never matches another robot's keys.
    pub fn new(prefix: &str) -> Result<Self, NetError> {
        vref_config::check_prefix(prefix).map_err(|reason| NetError::Prefix {
            prefix: prefix.to_owned(),
            reason,
        })?;
        Ok(Self {
            prefix: prefix.to_owned(),
        })
    }

    pub fn prefix(&self) -> &str {
        &self.prefix
    }

    fn key(&self, rest: &str) -> String {
        format!("{}/{rest}", self.prefix)
    }

    /// The headset's view, published by the headset.
    pub fn human_snapshot(&self) -> String {
        self.key("human/snapshot")
    }

    /// The headset's pointing rays.
    pub fn human_gesture(&self) -> String {
        self.key("human/gesture")
    }

    /// The queryable answering reference queries.
    pub fn reference(&self) -> String {
        self.key("reference")
    }

    /// The robot camera's view, published by the bridge.
    pub fn robot_snapshot(&self) -> String {
        self.key("robot/snapshot")
    }

    pub fn matcher_stats(&self) -> String {
        self.key("matcher/stats")
    }

    pub fn matcher_decision(&self) -> String {
        self.key("matcher/decision")
    }

    /// The bridge's own counters.
    pub fn bridge_stats(&self) -> String {
        self.key("bridge/stats")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_sit_under_the_prefix_and_wildcards_are_refused() {
        let keys = Keys::new("vref/r1").unwrap();
        assert_eq!(keys.human_snapshot(), "vref/r1/human/snapshot");
        assert_eq!(keys.reference(), "vref/r1/reference");
        assert_eq!(keys.bridge_stats(), "vref/r1/bridge/stats");
        assert_eq!(
            Keys::new("vref/*"),
            Err(NetError::Prefix {
                prefix: "vref/*".to_owned(),
                reason: vref_config::PrefixError::Character('*'),
            })
        );
    }
}
