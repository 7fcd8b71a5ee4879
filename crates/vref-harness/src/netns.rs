//! A network namespace with loopback only, for anything that starts DDS
//! (vref-ros2, rclpy): discovery is multicast, and inside the namespace it
//! never leaves the machine, so tests and benchmarks neither see nor
//! disturb other ROS 2 systems. `unshare --net` (util-linux) makes the
//! namespace and needs root; `ip` (iproute2) brings `lo` up and routes
//! multicast on it.

use std::path::Path;
use std::process::Command;

/// What runs inside the new namespace before the program: loopback up,
/// multicast (224.0.0.0/4) routed on it, then `exec` the program.
pub const LOOPBACK_SETUP: &str =
    "ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec \"$@\"";

/// Why the current process is not in a loopback-only namespace.
#[derive(Debug, thiserror::Error)]
pub enum NetnsError {
    #[error("listing the network interfaces ({path})")]
    List {
        path: String,
        #[source]
        source: std::io::Error,
    },
    #[error(
        "network interfaces other than lo are present ({0}): DDS would reach beyond this machine"
    )]
    NotLoopbackOnly(String),
}

/// `program` to be run in a new network namespace with only loopback up
/// (add its arguments to the command). Spawning fails where `unshare` is
/// missing; the command exits non-zero where the namespace cannot be made
/// (not root) or `ip` fails.
pub fn in_loopback_namespace(program: &Path) -> Command {
    let mut command = Command::new("unshare");
    command
        .args(["--net", "--", "sh", "-c", LOOPBACK_SETUP, "sh"])
        .arg(program);
    command
}

/// Checks that this process sees no network interface but `lo` (as inside
/// [`in_loopback_namespace`]). The list is the process's own network
/// namespace's (`/proc/self/net/dev`; `/sys/class/net` shows the
/// namespace sysfs was mounted in, which `unshare --net` keeps).
pub fn check_loopback_only() -> Result<(), NetnsError> {
    let path = "/proc/self/net/dev";
    let text = std::fs::read_to_string(path).map_err(|source| NetnsError::List {
        path: path.to_owned(),
        source,
    })?;
    let mut others: Vec<String> = text
        .lines()
        .filter_map(|line| line.split_once(':'))
        .map(|(name, _)| name.trim().to_owned())
        .filter(|name| name != "lo")
        .collect();
    if others.is_empty() {
        Ok(())
    } else {
        others.sort();
        Err(NetnsError::NotLoopbackOnly(others.join(", ")))
    }
}
