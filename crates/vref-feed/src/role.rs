use vref_scene::Side;

/// Which feed a process is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The robot's view.
    Perception,
    /// The person's view and pointing rays.
    Gesture,
}

impl Role {
    pub fn side(self) -> Side {
        match self {
            Role::Perception => Side::Robot,
            Role::Gesture => Side::Human,
        }
    }

    /// The camera frame its snapshots' positions are in.
    pub fn frame_name(self) -> &'static str {
        match self {
            Role::Perception => "robot_camera",
            Role::Gesture => "headset_camera",
        }
    }

    /// Its iceoryx2 node's name.
    pub fn node_name(self) -> &'static str {
        match self {
            Role::Perception => "vref-perception-feed",
            Role::Gesture => "vref-gesture-feed",
        }
    }

    /// Whether it publishes pointing rays.
    pub fn points(self) -> bool {
        self == Role::Gesture
    }
}
