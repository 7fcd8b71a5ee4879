//! Zenoh on loopback for tests of the bridge: every endpoint on
//! 127.0.0.1, sessions that do not scout.

use std::time::Duration;

/// A loopback port free a moment ago.
pub fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// A client session to a bridge listening on `endpoints`, once it
/// accepts connections (at most `limit`).
pub fn bridge_session(endpoints: &[String], limit: Duration) -> zenoh::Session {
    crate::eventually(limit, "the bridge listening", || {
        vref_bridge::open_client_session(endpoints).ok()
    })
}
