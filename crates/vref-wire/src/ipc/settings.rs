use std::path::PathBuf;

use serde::{Deserialize, Serialize};

/// Where and how vref's processes meet: the `[ipc]` section of
/// config/vref.toml.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct IpcSettings {
    /// Prefix of every service name, so several vref systems can share a
    /// machine.
    pub namespace: String,
    /// iceoryx2's own configuration file; default: iceoryx2's lookup
    /// ($PWD/config/iceoryx2.toml, then the user's and the system's).
    pub iceoryx2_config: Option<PathBuf>,
    /// iceoryx2 root path (its files); default: iceoryx2's (/tmp/iceoryx2/).
    pub root_path: Option<PathBuf>,
    /// Prefix of iceoryx2's files in /dev/shm and the root path.
    pub prefix: String,
    /// Objects a snapshot slice is first sized for; larger snapshots grow
    /// the segment (power of two).
    pub initial_objects: usize,
    /// Controllers that may query at once.
    pub max_clients: usize,
    /// Subscribers per feed (matcher, recorder, tools).
    pub max_subscribers: usize,
}

impl Default for IpcSettings {
    fn default() -> Self {
        Self {
            namespace: "vref".to_owned(),
            iceoryx2_config: None,
            root_path: None,
            prefix: "vref_".to_owned(),
            initial_objects: 64,
            max_clients: 16,
            max_subscribers: 8,
        }
    }
}
