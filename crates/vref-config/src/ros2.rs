//! The `[ros2]` section: what `vref-ros2` reads from and writes to a ROS 2
//! system (topic names, frame ids, how images are paired). Checked here
//! without DDS, so that every program reading the file refuses a bad
//! section the same way.

use serde::{Deserialize, Serialize};
use vref_perception::{DistortionUse, NoiseSource};

/// Environment variable ROS 2 uses for the DDS domain; it overrides
/// `domain_id` as it does for every ROS 2 node on the machine.
pub const ROS_DOMAIN_ID_ENV: &str = "ROS_DOMAIN_ID";

/// `ROS_DOMAIN_ID` is set but names no DDS domain; the value as set.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{ROS_DOMAIN_ID_ENV}={0:?} is not a domain id (0-232)", ROS_DOMAIN_ID_ENV = ROS_DOMAIN_ID_ENV)]
pub struct BadDomainId(pub String);

/// The `[ros2]` section of config/vref.toml.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Ros2Settings {
    /// DDS domain (0-232); `ROS_DOMAIN_ID` wins when set.
    pub domain_id: u16,
    /// The node's name and namespace as `ros2 node list` shows them.
    pub node_name: String,
    pub node_namespace: String,
    /// The robot camera: colour (rgb8, bgr8, rgba8, bgra8), registered depth (16UC1 in
    /// millimetres, 32FC1 in metres) and the colour camera's CameraInfo.
    pub colour_topic: String,
    pub depth_topic: String,
    pub camera_info_topic: String,
    /// Instance labels (16UC1/mono16, 0 background) from the user's
    /// segmenter; empty: vref's own segmenter labels every frame.
    pub labels_topic: String,
    /// Colour, depth and labels whose header stamps differ by at most this
    /// make one frame (milliseconds).
    pub stamp_tolerance_ms: f64,
    /// Each camera's per-reading depth noise (the segmenter's thresholds,
    /// the objects' stated errors): `frame` measured on the camera's first
    /// frame that shows enough depth and kept, `config` the configured
    /// `[perception]` law.
    pub depth_noise: NoiseSource,
    /// What a CameraInfo's lens distortion (`distortion_model`, `d`) is
    /// taken for: `rectify`, the images are raw and are rectified to the
    /// pinhole camera of K before anything else; `ignore`, they are
    /// rectified already (`image_rect` topics).
    pub distortion: DistortionUse,
    /// The headset's camera, the same way (empty: off; the headset's view
    /// then comes through vref-bridge or a feed).
    pub headset_colour_topic: String,
    pub headset_depth_topic: String,
    pub headset_camera_info_topic: String,
    pub headset_labels_topic: String,
    /// Pointing rays as geometry_msgs/PoseStamped in the headset camera's
    /// frame: origin the position, direction the pose's x axis (empty: off).
    pub pointing_topic: String,
    /// The cone half-angle (degrees) and confidence each ray is sent with.
    pub pointing_cone_deg: f64,
    pub pointing_confidence: f64,
    /// Frame ids of the robot camera (optical frame: x right, y down, z
    /// forward, as vref's positions) and of the headset camera.
    pub robot_frame_id: String,
    pub headset_frame_id: String,
    /// Outputs.
    pub markers_topic: String,
    pub referenced_object_topic: String,
    pub headset_pose_topic: String,
    pub latest_gesture_service: String,
    /// Most MarkerArray messages per second (one per new decision or
    /// snapshot, at most this often). Twice a camera's rate: a cap at the
    /// camera's own rate delays and skips frames (docs/ros2.md).
    pub marker_rate_hz: f64,
    /// How often the latest gesture is asked for, to publish each new ok
    /// answer on `referenced_object_topic`.
    pub answer_rate_hz: f64,
    /// How long a query to the matcher may take (milliseconds), for the
    /// service and the answers topic.
    pub query_timeout_ms: u64,
}

impl Default for Ros2Settings {
    fn default() -> Self {
        Self {
            domain_id: 0,
            node_name: "vref".to_owned(),
            node_namespace: "/".to_owned(),
            colour_topic: "/camera/camera/color/image_raw".to_owned(),
            depth_topic: "/camera/camera/aligned_depth_to_color/image_raw".to_owned(),
            camera_info_topic: "/camera/camera/color/camera_info".to_owned(),
            labels_topic: String::new(),
            headset_colour_topic: String::new(),
            headset_depth_topic: String::new(),
            headset_camera_info_topic: String::new(),
            headset_labels_topic: String::new(),
            pointing_topic: String::new(),
            pointing_cone_deg: 5.0,
            pointing_confidence: 1.0,
            stamp_tolerance_ms: 20.0,
            depth_noise: NoiseSource::Frame,
            distortion: DistortionUse::Rectify,
            robot_frame_id: "camera_color_optical_frame".to_owned(),
            headset_frame_id: "headset_camera".to_owned(),
            markers_topic: "/vref/markers".to_owned(),
            referenced_object_topic: "/vref/referenced_object".to_owned(),
            headset_pose_topic: "/vref/headset_pose".to_owned(),
            latest_gesture_service: "/vref/latest_gesture".to_owned(),
            marker_rate_hz: 60.0,
            answer_rate_hz: 10.0,
            query_timeout_ms: 500,
        }
    }
}

impl Ros2Settings {
    /// Whether the headset's camera comes over ROS 2.
    pub fn headset_camera(&self) -> bool {
        !self.headset_colour_topic.is_empty()
    }

    /// `ROS_DOMAIN_ID` if set (and valid), else `domain_id`.
    pub fn effective_domain_id(&self) -> Result<u16, BadDomainId> {
        match std::env::var(ROS_DOMAIN_ID_ENV) {
            Ok(text) if !text.trim().is_empty() => text
                .trim()
                .parse::<u16>()
                .ok()
                .filter(|d| *d <= 232)
                .ok_or(BadDomainId(text)),
            _ => Ok(self.domain_id),
        }
    }

    /// Why the section cannot be used, if it cannot.
    pub fn check(&self) -> Result<(), String> {
        if self.domain_id > 232 {
            return Err(format!(
                "domain_id is {}, but must be 0-232",
                self.domain_id
            ));
        }
        if self.node_name.is_empty() || self.node_name.contains('/') {
            return Err(format!(
                "node_name {:?} must be a plain name",
                self.node_name
            ));
        }
        if !self.node_namespace.starts_with('/') {
            return Err(format!(
                "node_namespace {:?} must start with /",
                self.node_namespace
            ));
        }
        for (name, topic) in [
            ("colour_topic", &self.colour_topic),
            ("depth_topic", &self.depth_topic),
            ("camera_info_topic", &self.camera_info_topic),
            ("markers_topic", &self.markers_topic),
            ("referenced_object_topic", &self.referenced_object_topic),
            ("headset_pose_topic", &self.headset_pose_topic),
            ("latest_gesture_service", &self.latest_gesture_service),
        ] {
            check_topic(name, topic)?;
        }
        for (name, topic) in [
            ("labels_topic", &self.labels_topic),
            ("headset_colour_topic", &self.headset_colour_topic),
            ("headset_depth_topic", &self.headset_depth_topic),
            ("headset_camera_info_topic", &self.headset_camera_info_topic),
            ("headset_labels_topic", &self.headset_labels_topic),
            ("pointing_topic", &self.pointing_topic),
        ] {
            if !topic.is_empty() {
                check_topic(name, topic)?;
            }
        }
        let headset = [
            &self.headset_colour_topic,
            &self.headset_depth_topic,
            &self.headset_camera_info_topic,
        ];
        if headset.iter().any(|t| t.is_empty()) && headset.iter().any(|t| !t.is_empty()) {
            return Err(
                "headset_colour_topic, headset_depth_topic and headset_camera_info_topic are set together or not at all"
                    .to_owned(),
            );
        }
        if self.headset_colour_topic.is_empty() && !self.headset_labels_topic.is_empty() {
            return Err("headset_labels_topic needs the headset's camera topics".to_owned());
        }
        let cone = self.pointing_cone_deg;
        if !(cone > 0.0 && cone < 90.0) {
            return Err(format!(
                "pointing_cone_deg is {cone}, but must be in (0, 90)"
            ));
        }
        if !(0.0..=1.0).contains(&self.pointing_confidence) {
            return Err(format!(
                "pointing_confidence is {}, but must be in [0, 1]",
                self.pointing_confidence
            ));
        }
        let tol = self.stamp_tolerance_ms;
        if !(0.0..=1000.0).contains(&tol) {
            return Err(format!(
                "stamp_tolerance_ms is {tol}, but must be in [0, 1000]"
            ));
        }
        for (name, id) in [
            ("robot_frame_id", &self.robot_frame_id),
            ("headset_frame_id", &self.headset_frame_id),
        ] {
            if id.is_empty() || id.len() > 32 {
                return Err(format!(
                    "{name} {id:?} must be 1 to 32 bytes (the wire's frame name)"
                ));
            }
        }
        for (name, rate) in [
            ("marker_rate_hz", self.marker_rate_hz),
            ("answer_rate_hz", self.answer_rate_hz),
        ] {
            if !(rate.is_finite() && rate > 0.0 && rate <= 1000.0) {
                return Err(format!("{name} is {rate}, but must be in (0, 1000]"));
            }
        }
        if self.query_timeout_ms == 0 {
            return Err("query_timeout_ms must be at least 1".to_owned());
        }
        Ok(())
    }
}

/// An absolute ROS 2 name: `/` then `/`-separated tokens of letters,
/// digits and `_`, none starting with a digit.
fn check_topic(name: &str, topic: &str) -> Result<(), String> {
    let bad = || format!("{name} {topic:?} is not an absolute ROS 2 name (/a/b_c)");
    let rest = topic.strip_prefix('/').ok_or_else(bad)?;
    if rest.is_empty() {
        return Err(bad());
    }
    for token in rest.split('/') {
        let first_ok = token
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
        if !first_ok || !token.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(bad());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
    use super::*;

    #[test]
    fn defaults_pass_and_name_the_realsense_topics() {
        let s = Ros2Settings::default();
        s.check().unwrap();
        assert_eq!(s.colour_topic, "/camera/camera/color/image_raw");
        assert!(!s.headset_camera());
    }

    #[test]
    fn bad_values_name_their_key() {
        let cases: Vec<(&str, Ros2Settings)> = vec![
            (
                "colour_topic",
                Ros2Settings {
                    colour_topic: "camera/no_slash".to_owned(),
                    ..Ros2Settings::default()
                },
            ),
            (
                "markers_topic",
                Ros2Settings {
                    markers_topic: "/vref/1bad".to_owned(),
                    ..Ros2Settings::default()
                },
            ),
            (
                "stamp_tolerance_ms",
                Ros2Settings {
                    stamp_tolerance_ms: f64::NAN,
                    ..Ros2Settings::default()
                },
            ),
            (
                "domain_id",
                Ros2Settings {
                    domain_id: 233,
                    ..Ros2Settings::default()
                },
            ),
            (
                "robot_frame_id",
                Ros2Settings {
                    robot_frame_id: "x".repeat(33),
                    ..Ros2Settings::default()
                },
            ),
            (
                "headset_colour_topic",
                Ros2Settings {
                    headset_colour_topic: "/headset/color".to_owned(),
                    ..Ros2Settings::default()
                },
            ),
            (
                "pointing_cone_deg",
                Ros2Settings {
                    pointing_cone_deg: 90.0,
                    ..Ros2Settings::default()
                },
            ),
        ];
        for (key, s) in cases {
            let message = s.check().unwrap_err();
            assert!(message.contains(key), "{message} should name {key}");
        }
    }

    #[test]
    fn the_headset_camera_needs_all_three_topics() {
        let s = Ros2Settings {
            headset_colour_topic: "/h/c".to_owned(),
            headset_depth_topic: "/h/d".to_owned(),
            headset_camera_info_topic: "/h/i".to_owned(),
            ..Ros2Settings::default()
        };
        s.check().unwrap();
        assert!(s.headset_camera());
    }

    #[test]
    fn a_bad_domain_id_names_the_variable_and_its_value() {
        assert_eq!(
            BadDomainId("300".to_owned()).to_string(),
            "ROS_DOMAIN_ID=\"300\" is not a domain id (0-232)"
        );
    }
}
