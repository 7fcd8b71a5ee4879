//! The `[bridge]` section: how `vref-bridge` joins this robot's iceoryx2
//! services to a Zenoh network (the headset, remote controllers, other
//! robots). Checked here without Zenoh, so that every program reading the
//! file refuses a bad section the same way.

use serde::{Deserialize, Serialize};

/// How the bridge takes part in the Zenoh network.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ZenohMode {
    /// Talks directly to headsets, controllers and other peers; accepts
    /// their connections on `listen`.
    Peer,
    /// Talks through a Zenoh router it reaches on `connect`.
    Client,
}

impl ZenohMode {
    pub fn name(self) -> &'static str {
        match self {
            ZenohMode::Peer => "peer",
            ZenohMode::Client => "client",
        }
    }
}

/// Which of the two encodings the bridge publishes the robot's state in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StateEncoding {
    Json,
    Binary,
}

/// The `[bridge]` section of config/vref.toml.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BridgeSettings {
    pub mode: ZenohMode,
    /// Endpoints the bridge accepts connections on, `tcp/HOST:PORT`.
    pub listen: Vec<String>,
    /// Endpoints the bridge connects to (a router, other peers).
    pub connect: Vec<String>,
    /// Zenoh's multicast scouting (peers finding each other on the LAN
    /// without endpoints). Off by default: the endpoints say who talks.
    pub multicast_scouting: bool,
    /// Every key of this robot starts with it, e.g. `vref/robot1`.
    pub prefix: String,
    /// Headset snapshots and rays from the network into the local services.
    pub headset_in: bool,
    /// Reference queries from the network answered by the local matcher.
    pub queries_in: bool,
    /// The robot's snapshots, the matcher's statistics and decision out.
    pub state_out: bool,
    /// Largest network payload accepted, bytes.
    pub max_message_bytes: usize,
    /// Most headset snapshots per second passed on to the matcher.
    pub max_snapshot_rate_hz: f64,
    /// Most pointing rays per second passed on.
    pub max_gesture_rate_hz: f64,
    /// Most remote queries per second answered.
    pub max_query_rate_hz: f64,
    /// Most messages per second of each kind of state published.
    pub state_rate_hz: f64,
    pub state_encoding: StateEncoding,
    /// How long a remote query may wait for the matcher, milliseconds.
    pub query_timeout_ms: u64,
    /// A headset session other than the current one is refused until the
    /// current one has been silent this long (milliseconds): one headset
    /// per robot, and a restarted headset takes over.
    pub session_takeover_ms: u64,
}

impl Default for BridgeSettings {
    fn default() -> Self {
        Self {
            mode: ZenohMode::Peer,
            listen: vec!["tcp/0.0.0.0:7447".to_owned()],
            connect: Vec::new(),
            multicast_scouting: false,
            prefix: "vref/robot".to_owned(),
            headset_in: true,
            queries_in: true,
            state_out: true,
            max_message_bytes: 256 * 1024,
            max_snapshot_rate_hz: 60.0,
            max_gesture_rate_hz: 60.0,
            max_query_rate_hz: 2000.0,
            state_rate_hz: 10.0,
            state_encoding: StateEncoding::Json,
            query_timeout_ms: 500,
            session_takeover_ms: 1000,
        }
    }
}

/// The transports this build of the bridge speaks.
pub const TRANSPORTS: [&str; 1] = ["tcp"];

impl BridgeSettings {
    /// The first problem of the section, naming the key.
    pub fn check(&self) -> Result<(), BridgeSettingsError> {
        check_prefix(&self.prefix).map_err(|reason| BridgeSettingsError::Prefix {
            prefix: self.prefix.clone(),
            reason,
        })?;
        for (key, list) in [("listen", &self.listen), ("connect", &self.connect)] {
            for endpoint in list {
                check_endpoint(endpoint).map_err(|reason| BridgeSettingsError::Endpoint {
                    key,
                    endpoint: endpoint.clone(),
                    reason,
                })?;
            }
        }
        if self.mode == ZenohMode::Client && self.connect.is_empty() && !self.multicast_scouting {
            return Err(BridgeSettingsError::ClientWithoutRouter);
        }
        if self.mode == ZenohMode::Client && !self.listen.is_empty() {
            return Err(BridgeSettingsError::ClientListens);
        }
        if !MESSAGE_BYTES.contains(&self.max_message_bytes) {
            return Err(BridgeSettingsError::MessageBytes {
                bytes: self.max_message_bytes,
            });
        }
        for (key, rate) in [
            ("max_snapshot_rate_hz", self.max_snapshot_rate_hz),
            ("max_gesture_rate_hz", self.max_gesture_rate_hz),
            ("max_query_rate_hz", self.max_query_rate_hz),
            ("state_rate_hz", self.state_rate_hz),
        ] {
            if !(rate.is_finite() && rate > 0.0 && rate <= MAX_RATE_HZ) {
                return Err(BridgeSettingsError::Rate { key, rate });
            }
        }
        for (key, ms) in [
            ("query_timeout_ms", self.query_timeout_ms),
            ("session_takeover_ms", self.session_takeover_ms),
        ] {
            if !MILLIS.contains(&ms) {
                return Err(BridgeSettingsError::Millis { key, ms });
            }
        }
        Ok(())
    }
}

/// The range of `max_message_bytes`.
const MESSAGE_BYTES: std::ops::RangeInclusive<usize> = 1024..=64 * 1024 * 1024;
/// The highest rate a `*_rate_hz` key may have.
const MAX_RATE_HZ: f64 = 100_000.0;
/// The range of the `*_ms` keys.
const MILLIS: std::ops::RangeInclusive<u64> = 1..=600_000;

/// Why a `[bridge]` section cannot be used: the first problem found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BridgeSettingsError {
    #[error("prefix `{prefix}`: {reason}")]
    Prefix { prefix: String, reason: PrefixError },
    #[error("{key}: `{endpoint}`: {reason}")]
    Endpoint {
        key: &'static str,
        endpoint: String,
        reason: EndpointError,
    },
    #[error("mode client needs a router to reach: set connect, or multicast_scouting")]
    ClientWithoutRouter,
    #[error("listen must be empty in mode client (clients do not listen)")]
    ClientListens,
    #[error(
        "max_message_bytes is {bytes}, but must be in [{}, {}]",
        MESSAGE_BYTES.start(),
        MESSAGE_BYTES.end()
    )]
    MessageBytes { bytes: usize },
    #[error("{key} is {rate}, but must be in (0, {}]", MAX_RATE_HZ)]
    Rate { key: &'static str, rate: f64 },
    #[error("{key} is {ms}, but must be in [{}, {}]", MILLIS.start(), MILLIS.end())]
    Millis { key: &'static str, ms: u64 },
}

/// Why a key prefix is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PrefixError {
    #[error("empty")]
    Empty,
    #[error("empty chunk (leading, trailing or double `/`)")]
    EmptyChunk,
    #[error("`{0}` is not allowed (letters, digits, `-`, `_`, `.` and `/` only)")]
    Character(char),
}

/// Why an endpoint is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EndpointError {
    #[error("not TRANSPORT/HOST:PORT")]
    Form,
    #[error("transport `{transport}` is not built in (only {})", TRANSPORTS.join(", "))]
    Transport { transport: String },
    #[error("no `:PORT`")]
    NoPort,
    #[error("host `{0}` is not a host name or address")]
    Host(String),
    #[error("host `{0}`: unbalanced brackets")]
    Brackets(String),
    #[error("port `{0}` is not a number in [0, 65535]")]
    Port(String),
}

/// A key prefix: slash-separated chunks of letters, digits, `-`, `_`
/// and `.`, no wildcards (`*`, `$`), no empty chunk, so that it names
/// one robot and never matches another's keys.
pub fn check_prefix(prefix: &str) -> Result<(), PrefixError> {
    if prefix.is_empty() {
        return Err(PrefixError::Empty);
    }
    for chunk in prefix.split('/') {
        if chunk.is_empty() {
            return Err(PrefixError::EmptyChunk);
        }
        if let Some(c) = chunk
            .chars()
            .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.')))
        {
            return Err(PrefixError::Character(c));
        }
    }
    Ok(())
}

/// An endpoint `tcp/HOST:PORT` (IPv6 hosts in brackets).
pub fn check_endpoint(endpoint: &str) -> Result<(), EndpointError> {
    let Some((transport, address)) = endpoint.split_once('/') else {
        return Err(EndpointError::Form);
    };
    if !TRANSPORTS.contains(&transport) {
        return Err(EndpointError::Transport {
            transport: transport.to_owned(),
        });
    }
    let Some((host, port)) = address.rsplit_once(':') else {
        return Err(EndpointError::NoPort);
    };
    if host.is_empty() || host.contains(['/', '?', '#', ' ']) {
        return Err(EndpointError::Host(host.to_owned()));
    }
    if host.starts_with('[') != host.ends_with(']') {
        return Err(EndpointError::Brackets(host.to_owned()));
    }
    port.parse::<u16>()
        .map_err(|_| EndpointError::Port(port.to_owned()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_pass() {
        assert_eq!(BridgeSettings::default().check(), Ok(()));
    }

    #[test]
    fn prefixes_with_wildcards_or_empty_chunks_are_refused() {
        for good in ["vref/robot1", "vref/r-2/arm_a", "x"] {
            assert_eq!(check_prefix(good), Ok(()), "{good}");
        }
        for (bad, reason) in [
            ("", PrefixError::Empty),
            ("vref/", PrefixError::EmptyChunk),
            ("/vref", PrefixError::EmptyChunk),
            ("vref//r", PrefixError::EmptyChunk),
            ("vref/*", PrefixError::Character('*')),
            ("vref/**", PrefixError::Character('*')),
            ("vref/$*r", PrefixError::Character('$')),
            ("a b", PrefixError::Character(' ')),
        ] {
            assert_eq!(check_prefix(bad), Err(reason), "{bad}");
        }
    }

    #[test]
    fn endpoints_must_be_tcp_host_port() {
        for good in ["tcp/127.0.0.1:7447", "tcp/[::1]:0", "tcp/robot.local:7447"] {
            assert_eq!(check_endpoint(good), Ok(()), "{good}");
        }
        for (bad, reason, says) in [
            ("127.0.0.1:7447", EndpointError::Form, "TRANSPORT"),
            (
                "udp/127.0.0.1:7447",
                EndpointError::Transport {
                    transport: "udp".to_owned(),
                },
                "udp",
            ),
            ("tcp/127.0.0.1", EndpointError::NoPort, ":PORT"),
            (
                "tcp/127.0.0.1:70000",
                EndpointError::Port("70000".to_owned()),
                "70000",
            ),
            ("tcp/:7447", EndpointError::Host(String::new()), "host"),
            (
                "tcp/[::1:7447",
                EndpointError::Brackets("[::1".to_owned()),
                "brackets",
            ),
        ] {
            let e = check_endpoint(bad).unwrap_err();
            assert_eq!(e, reason, "{bad}");
            assert!(e.to_string().contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn a_client_needs_a_router_and_does_not_listen() {
        let client = BridgeSettings {
            mode: ZenohMode::Client,
            listen: Vec::new(),
            ..BridgeSettings::default()
        };
        let e = client.check().unwrap_err();
        assert_eq!(e, BridgeSettingsError::ClientWithoutRouter);
        assert!(e.to_string().contains("connect"));
        let with_router = BridgeSettings {
            connect: vec!["tcp/127.0.0.1:7447".to_owned()],
            ..client.clone()
        };
        assert_eq!(with_router.check(), Ok(()));
        let listening = BridgeSettings {
            listen: vec!["tcp/0.0.0.0:7447".to_owned()],
            ..with_router
        };
        let e = listening.check().unwrap_err();
        assert_eq!(e, BridgeSettingsError::ClientListens);
        assert!(e.to_string().contains("listen"));
    }

    #[test]
    fn bad_prefixes_and_endpoints_name_the_key_and_value() {
        let s = BridgeSettings {
            prefix: "vref/*".to_owned(),
            ..BridgeSettings::default()
        };
        assert_eq!(
            s.check().unwrap_err().to_string(),
            "prefix `vref/*`: `*` is not allowed (letters, digits, `-`, `_`, `.` and `/` only)"
        );
        let s = BridgeSettings {
            connect: vec!["udp/127.0.0.1:7447".to_owned()],
            ..BridgeSettings::default()
        };
        assert_eq!(
            s.check().unwrap_err().to_string(),
            "connect: `udp/127.0.0.1:7447`: transport `udp` is not built in (only tcp)"
        );
    }

    #[test]
    fn limits_out_of_range_name_their_key_and_range() {
        let mut s = BridgeSettings {
            max_snapshot_rate_hz: f64::NAN,
            ..BridgeSettings::default()
        };
        assert_eq!(
            s.check().unwrap_err().to_string(),
            "max_snapshot_rate_hz is NaN, but must be in (0, 100000]"
        );
        s.max_snapshot_rate_hz = 30.0;
        s.query_timeout_ms = 0;
        assert_eq!(
            s.check().unwrap_err().to_string(),
            "query_timeout_ms is 0, but must be in [1, 600000]"
        );
        s.query_timeout_ms = 500;
        s.max_message_bytes = 10;
        assert_eq!(
            s.check().unwrap_err().to_string(),
            "max_message_bytes is 10, but must be in [1024, 67108864]"
        );
    }
}
