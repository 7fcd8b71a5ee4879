//! A rosbag2 file (MCAP, ROS 2's default storage) as a camera: the
//! `[ros2]` topics' Image and CameraInfo messages, CDR-decoded, checked
//! and paired by stamp as vref-ros2 does with live topics ([`decode`],
//! [`pairing`]), each frame through the same [`Perception`]. The whole file
//! is measured at once; the feeds replay the frames with the bag's timing.
//!
//! A file that cannot be a camera is an error naming what is wrong: not
//! there, not MCAP, a topic missing (with the topics it has), a topic of
//! another type or message encoding, a message that is not CDR of its
//! type, an image encoding vref does not take. A frame the front end finds
//! nothing in is counted and left out, as vref-ros2 does.
//!
//! [`decode`]: crate::decode
//! [`pairing`]: crate::pairing

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use vref_config::Config;
use vref_perception::{DepthImage, DistortionUse, LabelImage};
use vref_scene::Side;

use crate::cdr::{CdrError, from_cdr};
use crate::decode::{self, CameraModel, DecodeError};
use crate::msg;
use crate::pairing::Pairer;
use crate::perceive::{Perceived, Perception};
use vref_feed::BagSnapshot;
use vref_perception::ImageLimit;

const IMAGE: &str = "sensor_msgs/msg/Image";
const CAMERA_INFO: &str = "sensor_msgs/msg/CameraInfo";

/// Why a bag cannot be read as a camera.
#[derive(Debug, thiserror::Error)]
pub enum BagError {
    #[error("cannot read {path}")]
    Open {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error(
        "{path} is not an MCAP file (it does not start with MCAP's magic bytes; rosbag2's default storage is MCAP, a .db3 bag needs `ros2 bag convert`)"
    )]
    NotMcap { path: PathBuf },
    #[error("{path}: reading its messages")]
    Mcap {
        path: PathBuf,
        #[source]
        source: mcap::McapError,
    },
    #[error("{path}: no messages on topic {topic} ({role}); topics with messages: {found}")]
    TopicMissing {
        path: PathBuf,
        topic: String,
        role: &'static str,
        found: String,
    },
    #[error("{path}: topic {topic} carries {found:?}, not {expected}")]
    Schema {
        path: PathBuf,
        topic: String,
        found: String,
        expected: &'static str,
    },
    #[error("{path}: topic {topic} has message encoding {found:?}; only cdr (ROS 2's) is read")]
    MessageEncoding {
        path: PathBuf,
        topic: String,
        found: String,
    },
    #[error("{path}: message {index} on {topic}")]
    Cdr {
        path: PathBuf,
        topic: String,
        index: u64,
        #[source]
        source: CdrError,
    },
    #[error("{path}: message {index} on {topic}")]
    Message {
        path: PathBuf,
        topic: String,
        index: u64,
        #[source]
        source: DecodeError,
    },
    #[error("{path}: none of its {frames} frames gave objects ({skipped})")]
    NoObjects {
        path: PathBuf,
        frames: u64,
        skipped: String,
    },
}

impl BagError {
    /// A short name per kind, for tests and counters.
    pub fn reason(&self) -> &'static str {
        match self {
            BagError::Open { .. } => "open",
            BagError::NotMcap { .. } => "not_mcap",
            BagError::Mcap { .. } => "mcap",
            BagError::TopicMissing { .. } => "topic_missing",
            BagError::Schema { .. } => "schema",
            BagError::MessageEncoding { .. } => "message_encoding",
            BagError::Cdr { .. } => "cdr",
            BagError::Message { source, .. } => source.reason(),
            BagError::NoObjects { .. } => "no_objects",
        }
    }
}

/// The topics of one camera in a bag.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BagTopics {
    pub colour: String,
    pub depth: String,
    pub camera_info: String,
    /// Instance labels; `None`: vref's segmenter labels each frame.
    pub labels: Option<String>,
}

impl BagTopics {
    /// `side`'s camera topics of `[ros2]`: the headset's where they are
    /// set, otherwise (and for the robot) the robot camera's.
    pub fn of(s: &vref_config::Ros2Settings, side: Side) -> Self {
        let some = |t: &str| (!t.is_empty()).then(|| t.to_owned());
        if side == Side::Human && s.headset_camera() {
            Self {
                colour: s.headset_colour_topic.clone(),
                depth: s.headset_depth_topic.clone(),
                camera_info: s.headset_camera_info_topic.clone(),
                labels: some(&s.headset_labels_topic),
            }
        } else {
            Self {
                colour: s.colour_topic.clone(),
                depth: s.depth_topic.clone(),
                camera_info: s.camera_info_topic.clone(),
                labels: some(&s.labels_topic),
            }
        }
    }
}

/// What was read.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BagSummary {
    /// Messages read per stream (colour, depth, labels, camera_info).
    pub messages: BTreeMap<&'static str, u64>,
    /// Frames paired (colour, depth and labels if wanted, within the
    /// stamp tolerance).
    pub paired: u64,
    /// Paired frames left out, by reason ([`crate::perceive::PerceiveError`]).
    pub skipped: BTreeMap<&'static str, u64>,
    /// Images that found no partners.
    pub unpaired: u64,
    /// Objects over all frames kept.
    pub objects: u64,
}

/// The bag's frames that gave objects, in stamp order (each the colour
/// image's stamp, its objects and, where vref's segmenter found the
/// support, the camera's up vector), and the counts.
#[derive(Debug, Clone, PartialEq)]
pub struct Bag {
    pub frames: Vec<BagSnapshot>,
    pub summary: BagSummary,
}

/// Reads `path` as `side`'s camera with `config`'s `[ros2]` topics, stamp
/// tolerance and size limits, `[perception]`, `[segmentation]` and
/// `[scene] capacity`, as vref-ros2 would see the same messages live.
pub fn read_bag(path: &Path, side: Side, config: &Config) -> Result<Bag, BagError> {
    let s = &config.ros2;
    let front_end = match side {
        Side::Robot => config.perception.robot(),
        Side::Human => config.perception.human(),
    };
    let mut perception = Perception::new(
        front_end,
        config.segmentation,
        s.depth_noise,
        config.scene.capacity,
    );
    let settings = BagSettings {
        topics: BagTopics::of(s, side),
        max: config.perception.image_limit(),
        tolerance_ns: (s.stamp_tolerance_ms * 1e6).round() as u64,
        distortion: s.distortion,
    };
    read_with(path, &settings, &mut perception)
}

/// What [`read_with`] needs besides the perception.
#[derive(Debug, Clone)]
pub struct BagSettings {
    pub topics: BagTopics,
    pub max: ImageLimit,
    pub tolerance_ns: u64,
    /// What the CameraInfo's lens distortion is taken for.
    pub distortion: DistortionUse,
}

/// Which of the camera's streams a topic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    Colour,
    Depth,
    Labels,
    Info,
}

impl Role {
    fn name(self) -> &'static str {
        match self {
            Role::Colour => "colour",
            Role::Depth => "depth",
            Role::Labels => "labels",
            Role::Info => "camera_info",
        }
    }
}

/// [`read_bag`] with its settings spelled out.
pub fn read_with(
    path: &Path,
    settings: &BagSettings,
    perception: &mut Perception,
) -> Result<Bag, BagError> {
    let bytes = std::fs::read(path).map_err(|source| BagError::Open {
        path: path.to_owned(),
        source,
    })?;
    let t = &settings.topics;
    let mut roles: Vec<(&str, Role)> = vec![
        (&t.colour, Role::Colour),
        (&t.depth, Role::Depth),
        (&t.camera_info, Role::Info),
    ];
    if let Some(labels) = &t.labels {
        roles.push((labels, Role::Labels));
    }
    let role_of = |topic: &str| roles.iter().find(|(t, _)| *t == topic).map(|(_, r)| *r);
    let read_error = |source| BagError::Mcap {
        path: path.to_owned(),
        source,
    };

    // First pass: the topics there are, their types, and the camera
    // models (a CameraInfo may come after the first images).
    let mut found: BTreeMap<String, String> = BTreeMap::new();
    let mut models: Vec<(u64, CameraModel)> = Vec::new();
    let mut info_index = 0u64;
    for message in open_stream(path, &bytes)? {
        let message = message.map_err(read_error)?;
        let topic = &message.channel.topic;
        if !found.contains_key(topic) {
            let schema = message
                .channel
                .schema
                .as_ref()
                .map_or_else(String::new, |s| s.name.clone());
            if let Some(role) = role_of(topic) {
                check_channel(path, &message.channel, role)?;
            }
            found.insert(topic.clone(), schema);
        }
        if role_of(topic) == Some(Role::Info) {
            let info: msg::CameraInfo =
                from_cdr(&message.data).map_err(|source| BagError::Cdr {
                    path: path.to_owned(),
                    topic: topic.clone(),
                    index: info_index,
                    source,
                })?;
            let model = decode::stamp_ns(info.header.stamp)
                .and_then(|stamp| Ok((stamp, decode::camera_model(&info, settings.distortion)?)))
                .map_err(|source| BagError::Message {
                    path: path.to_owned(),
                    topic: topic.clone(),
                    index: info_index,
                    source,
                })?;
            models.push(model);
            info_index += 1;
        }
    }
    for (topic, role) in &roles {
        if !found.contains_key(*topic) {
            return Err(BagError::TopicMissing {
                path: path.to_owned(),
                topic: (*topic).to_owned(),
                role: role.name(),
                found: if found.is_empty() {
                    "none".to_owned()
                } else {
                    found
                        .iter()
                        .map(|(t, s)| format!("{t} ({s})"))
                        .collect::<Vec<_>>()
                        .join(", ")
                },
            });
        }
    }
    models.sort_by_key(|(stamp, _)| *stamp);

    // Second pass: the images, paired as they come.
    let mut pairer: Pairer<image::RgbImage, DepthImage, LabelImage> =
        Pairer::new(settings.tolerance_ns, t.labels.is_some());
    let mut summary = BagSummary::default();
    let mut frames = Vec::new();
    let mut index: BTreeMap<&'static str, u64> = BTreeMap::new();
    for message in open_stream(path, &bytes)? {
        let message = message.map_err(read_error)?;
        let topic = &message.channel.topic;
        let role = match role_of(topic) {
            Some(Role::Info) | None => continue,
            Some(role) => role,
        };
        let n = index.entry(role.name()).or_insert(0);
        let at = *n;
        *n += 1;
        *summary.messages.entry(role.name()).or_insert(0) += 1;
        let image: msg::Image = from_cdr(&message.data).map_err(|source| BagError::Cdr {
            path: path.to_owned(),
            topic: topic.clone(),
            index: at,
            source,
        })?;
        let max = settings.max;
        let pushed = decode::stamp_ns(image.header.stamp).and_then(|stamp| match role {
            Role::Colour => pairer.push_colour(stamp, decode::colour(&image, max)?),
            Role::Depth => pairer.push_depth(stamp, decode::depth(&image, max)?),
            _ => pairer.push_labels(stamp, decode::labels(&image, max)?),
        });
        pushed.map_err(|source| BagError::Message {
            path: path.to_owned(),
            topic: topic.clone(),
            index: at,
            source,
        })?;
        while let Some(frame) = pairer.take() {
            summary.paired += 1;
            // The latest camera model at the frame's stamp, else the first.
            let at_or_before = models.partition_point(|(s, _)| *s <= frame.stamp_ns);
            let Some((_, camera)) = models.get(at_or_before.saturating_sub(1)) else {
                *summary.skipped.entry("no_camera_info").or_insert(0) += 1;
                continue;
            };
            let (w, h) = frame.colour.dimensions();
            let stated = (camera.width, camera.height);
            if stated != (0, 0) && stated != (w, h) {
                *summary.skipped.entry("info_size").or_insert(0) += 1;
                continue;
            }
            match perception.process(&frame.colour, &frame.depth, camera, frame.labels.as_ref()) {
                Ok(Perceived { entries, up }) => {
                    summary.objects += entries.len() as u64;
                    frames.push(BagSnapshot {
                        stamp_ns: frame.stamp_ns,
                        entries: entries.to_vec(),
                        up,
                    });
                }
                Err(e) => {
                    tracing::debug!(stamp_ns = frame.stamp_ns, "frame left out: {e}");
                    *summary.skipped.entry(e.reason()).or_insert(0) += 1;
                }
            }
        }
    }
    summary.unpaired = pairer.unpaired;
    if frames.is_empty() {
        return Err(BagError::NoObjects {
            path: path.to_owned(),
            frames: summary.paired,
            skipped: if summary.skipped.is_empty() {
                "no colour and depth image paired up".to_owned()
            } else {
                summary
                    .skipped
                    .iter()
                    .map(|(r, n)| format!("{r}: {n}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            },
        });
    }
    Ok(Bag { frames, summary })
}

fn open_stream<'a>(path: &Path, bytes: &'a [u8]) -> Result<mcap::MessageStream<'a>, BagError> {
    if !bytes.starts_with(mcap::MAGIC) {
        return Err(BagError::NotMcap {
            path: path.to_owned(),
        });
    }
    mcap::MessageStream::new(bytes).map_err(|source| BagError::Mcap {
        path: path.to_owned(),
        source,
    })
}

/// A camera topic must be the right type in ROS 2's encoding.
fn check_channel(path: &Path, channel: &mcap::Channel<'_>, role: Role) -> Result<(), BagError> {
    if channel.message_encoding != "cdr" {
        return Err(BagError::MessageEncoding {
            path: path.to_owned(),
            topic: channel.topic.clone(),
            found: channel.message_encoding.clone(),
        });
    }
    let expected = match role {
        Role::Info => CAMERA_INFO,
        _ => IMAGE,
    };
    let found = channel.schema.as_ref().map_or("", |s| s.name.as_str());
    if found != expected {
        return Err(BagError::Schema {
            path: path.to_owned(),
            topic: channel.topic.clone(),
            found: found.to_owned(),
            expected,
        });
    }
    Ok(())
}

/// The feeds' reader of `--source rosbag:FILE.mcap` ([`read_bag`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct FeedBags;

impl vref_feed::BagReader for FeedBags {
    fn read(
        &self,
        path: &Path,
        side: Side,
        config: &Config,
    ) -> Result<vref_feed::MeasuredBag, Box<dyn std::error::Error + Send + Sync>> {
        let bag = read_bag(path, side, config)?;
        let s = &bag.summary;
        let mut description = format!(
            "{} frames with objects of {} paired, {} objects; messages {}",
            bag.frames.len(),
            s.paired,
            s.objects,
            s.messages
                .iter()
                .map(|(k, n)| format!("{k} {n}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        if !s.skipped.is_empty() {
            description.push_str(&format!(
                "; left out: {}",
                s.skipped
                    .iter()
                    .map(|(k, n)| format!("{k} {n}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        if s.unpaired > 0 {
            description.push_str(&format!("; {} images unpaired", s.unpaired));
        }
        Ok(vref_feed::MeasuredBag {
            frames: bag.frames,
            description,
        })
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
    use super::*;
    use crate::cdr::to_cdr;

    /// One message per channel: (topic, schema name, message encoding,
    /// data).
    fn write(path: &Path, channels: &[(&str, &str, &str, Vec<u8>)]) {
        let file = std::fs::File::create(path).unwrap();
        let mut w = mcap::WriteOptions::new()
            .profile("ros2")
            .create(std::io::BufWriter::new(file))
            .unwrap();
        for (k, (topic, schema, encoding, data)) in channels.iter().enumerate() {
            let s = w.add_schema(schema, "ros2msg", b"").unwrap();
            let c = w.add_channel(s, topic, encoding, &BTreeMap::new()).unwrap();
            w.write_to_known_channel(
                &mcap::records::MessageHeader {
                    channel_id: c,
                    sequence: k as u32,
                    log_time: k as u64,
                    publish_time: k as u64,
                },
                data,
            )
            .unwrap();
        }
        w.finish().unwrap();
    }

    fn read(path: &Path) -> Result<Bag, BagError> {
        let settings = BagSettings {
            topics: BagTopics {
                colour: "/c".to_owned(),
                depth: "/d".to_owned(),
                camera_info: "/i".to_owned(),
                labels: None,
            },
            max: Config::default().perception.image_limit(),
            tolerance_ns: 0,
            distortion: DistortionUse::Rectify,
        };
        let config = Config::default();
        let mut perception = Perception::new(
            config.perception.robot(),
            config.segmentation,
            config.ros2.depth_noise,
            config.scene.capacity,
        );
        read_with(path, &settings, &mut perception)
    }

    fn info() -> Vec<u8> {
        to_cdr(&msg::CameraInfo {
            k: [500.0, 0.0, 1.0, 0.0, 500.0, 1.0, 0.0, 0.0, 1.0],
            width: 2,
            height: 2,
            ..msg::CameraInfo::default()
        })
        .unwrap()
    }

    fn image(encoding: &str, bytes_per_pixel: u32) -> Vec<u8> {
        to_cdr(&msg::Image {
            header: msg::Header {
                stamp: msg::Time { sec: 1, nanosec: 0 },
                frame_id: String::new(),
            },
            width: 2,
            height: 2,
            step: 2 * bytes_per_pixel,
            encoding: encoding.to_owned(),
            data: vec![0; 4 * bytes_per_pixel as usize],
            ..msg::Image::default()
        })
        .unwrap()
    }

    #[test]
    fn files_that_are_not_a_camera_give_their_reason() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("b.mcap");

        assert_eq!(read(&p).unwrap_err().reason(), "open");
        std::fs::write(&p, b"SQLite format 3\0").unwrap();
        assert_eq!(read(&p).unwrap_err().reason(), "not_mcap");

        write(&p, &[("/c", IMAGE, "cdr", image("rgb8", 3))]);
        let e = read(&p).unwrap_err();
        assert_eq!(e.reason(), "topic_missing");
        let text = e.to_string();
        assert!(
            text.contains("topic /d (depth)") && text.contains("/c (sensor_msgs/msg/Image)"),
            "{text}"
        );

        write(
            &p,
            &[
                ("/c", IMAGE, "cdr", image("rgb8", 3)),
                ("/d", "std_msgs/msg/String", "cdr", image("16UC1", 2)),
            ],
        );
        let e = read(&p).unwrap_err();
        assert!(
            e.to_string()
                .contains("\"std_msgs/msg/String\", not sensor_msgs/msg/Image"),
            "{e}"
        );

        write(&p, &[("/i", CAMERA_INFO, "cdr", vec![0, 1, 0, 0, 7])]);
        assert_eq!(read(&p).unwrap_err().reason(), "cdr");

        write(
            &p,
            &[
                ("/i", CAMERA_INFO, "cdr", info()),
                ("/c", IMAGE, "cdr", image("yuv422", 2)),
                ("/d", IMAGE, "cdr", image("16UC1", 2)),
            ],
        );
        let e = read(&p).unwrap_err();
        assert_eq!(e.reason(), "encoding");
        assert!(
            vref_logging::with_causes(&e).contains("message 0 on /c: encoding \"yuv422\""),
            "{}",
            vref_logging::with_causes(&e)
        );
    }

    #[test]
    fn frames_without_objects_are_counted_and_an_empty_result_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("b.mcap");
        // A 2x2 frame of no depth: paired, then nothing to measure.
        write(
            &p,
            &[
                ("/i", CAMERA_INFO, "cdr", info()),
                ("/c", IMAGE, "cdr", image("rgb8", 3)),
                ("/d", IMAGE, "cdr", image("16UC1", 2)),
            ],
        );
        match read(&p).unwrap_err() {
            BagError::NoObjects {
                frames, skipped, ..
            } => {
                assert_eq!(frames, 1);
                assert!(!skipped.is_empty());
            }
            other => panic!("{other}"),
        }
    }
}
