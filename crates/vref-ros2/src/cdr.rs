//! CDR as ROS 2 stores it in files (rosbag2's MCAP, message encoding
//! `cdr`): a 4-byte encapsulation header, then the message in plain CDR,
//! aligned from the end of the header. The encoder is `cdr-encoding`, the
//! one RustDDS uses on the wire, so a message reads the same from a bag
//! and from a subscription.

use byteorder::{BigEndian, LittleEndian};
use serde::Serialize;
use serde::de::DeserializeOwned;

/// Plain CDR, big-endian and little-endian (the representation
/// identifiers of the DDS-XTypes specification, as rosbag2 writes them).
const CDR_BE: [u8; 2] = [0x00, 0x00];
const CDR_LE: [u8; 2] = [0x00, 0x01];

/// Why bytes are not a CDR message of the expected type.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CdrError {
    #[error("{len} bytes, shorter than the 4-byte CDR encapsulation header")]
    Short { len: usize },
    #[error("encapsulation {0:#06x} is not plain CDR (0x0000 big-endian or 0x0001 little-endian)")]
    Encapsulation(u16),
    #[error("not a {type_name}: {message}")]
    Decode {
        type_name: &'static str,
        message: String,
    },
    #[error("encoding a {type_name}: {message}")]
    Encode {
        type_name: &'static str,
        message: String,
    },
}

/// A message from its encapsulated CDR bytes.
pub fn from_cdr<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, CdrError> {
    let (header, body) = bytes
        .split_first_chunk::<4>()
        .ok_or(CdrError::Short { len: bytes.len() })?;
    let decoded = match [header[0], header[1]] {
        CDR_LE => cdr_encoding::from_bytes::<T, LittleEndian>(body),
        CDR_BE => cdr_encoding::from_bytes::<T, BigEndian>(body),
        other => return Err(CdrError::Encapsulation(u16::from_be_bytes(other))),
    };
    decoded
        .map(|(value, _)| value)
        .map_err(|e| CdrError::Decode {
            type_name: std::any::type_name::<T>(),
            message: e.to_string(),
        })
}

/// A message as encapsulated little-endian CDR, as ROS 2 on x86 and ARM
/// sends and stores it.
pub fn to_cdr<T: Serialize>(value: &T) -> Result<Vec<u8>, CdrError> {
    let body = cdr_encoding::to_vec::<T, LittleEndian>(value).map_err(|e| CdrError::Encode {
        type_name: std::any::type_name::<T>(),
        message: e.to_string(),
    })?;
    let mut bytes = Vec::with_capacity(4 + body.len());
    bytes.extend_from_slice(&[CDR_LE[0], CDR_LE[1], 0, 0]);
    bytes.extend_from_slice(&body);
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
    use super::*;
    use crate::msg::{Header, Image, Point, PointStamped, Time};

    #[test]
    fn a_message_survives_the_round_trip() {
        let image = Image {
            header: Header {
                stamp: Time { sec: 7, nanosec: 9 },
                frame_id: "cam".to_owned(),
            },
            height: 1,
            width: 2,
            encoding: "rgb8".to_owned(),
            is_bigendian: 0,
            step: 6,
            data: vec![1, 2, 3, 4, 5, 6],
        };
        let bytes = to_cdr(&image).unwrap();
        assert_eq!(&bytes[..4], &[0, 1, 0, 0]);
        assert_eq!(from_cdr::<Image>(&bytes).unwrap(), image);
    }

    #[test]
    fn the_layout_is_ros_2s() {
        // geometry_msgs/PointStamped, little-endian: sec, nanosec, the
        // frame id (length with its NUL, bytes, NUL), padding to 8, x y z.
        let p = PointStamped {
            header: Header {
                stamp: Time { sec: 1, nanosec: 2 },
                frame_id: "ab".to_owned(),
            },
            point: Point::from([1.0, 2.0, 3.0]),
        };
        let bytes = to_cdr(&p).unwrap();
        let mut expected = vec![
            0, 1, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, b'a', b'b', 0,
        ];
        expected.push(0);
        for v in [1.0f64, 2.0, 3.0] {
            expected.extend_from_slice(&v.to_le_bytes());
        }
        assert_eq!(bytes, expected);
    }

    #[test]
    fn bad_headers_and_truncated_bodies_are_errors() {
        assert_eq!(from_cdr::<Image>(&[0, 1]), Err(CdrError::Short { len: 2 }));
        assert_eq!(
            from_cdr::<Image>(&[0, 7, 0, 0, 1]),
            Err(CdrError::Encapsulation(7))
        );
        let mut bytes = to_cdr(&Image::default()).unwrap();
        bytes.truncate(bytes.len() - 3);
        assert!(matches!(
            from_cdr::<Image>(&bytes),
            Err(CdrError::Decode { .. })
        ));
    }
}
