#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use proptest::prelude::*;
use vref_record::{
    Frame, RecordError, RecordedObject, RecordedRay, RecordedSnapshot, RecordingReader,
    RecordingWriter,
};

fn frames() -> Vec<Frame> {
    vec![
        Frame::Snapshot(RecordedSnapshot {
            robot: true,
            sequence: 1,
            timestamp_ns: 1_000,
            frame_name: "robot_camera".to_owned(),
            feature_dim: 2,
            objects: vec![RecordedObject {
                track_id: 7,
                position: [0.1, -0.2, 1.5],
                position_sigma: [0.01, 0.01, 0.03],
                feature: vec![0.5, 0.25],
            }],
            up: Some([0.0, -0.6, 0.8]),
        }),
        Frame::Snapshot(RecordedSnapshot {
            robot: false,
            sequence: 1,
            timestamp_ns: 1_200,
            frame_name: "headset_camera".to_owned(),
            feature_dim: 0,
            objects: vec![],
            up: None,
        }),
        Frame::Gesture(RecordedRay {
            sequence: 1,
            timestamp_ns: 1_500,
            origin: [0.0; 3],
            direction: [0.0, 0.1, 1.0],
            cone_half_angle: 0.1,
            confidence: 0.9,
        }),
    ]
}

fn encode(frames: &[Frame]) -> Vec<u8> {
    let mut w = RecordingWriter::new(Vec::new()).unwrap();
    for f in frames {
        w.write(f).unwrap();
    }
    assert_eq!(w.frames(), frames.len() as u64);
    w.finish().unwrap()
}

#[test]
fn frames_round_trip_in_order() {
    let bytes = encode(&frames());
    let back: Vec<Frame> = RecordingReader::new(&bytes[..])
        .unwrap()
        .map(Result::unwrap)
        .collect();
    assert_eq!(back, frames());
    assert_eq!(back[2].timestamp_ns(), 1_500);
}

#[test]
fn damage_is_reported_by_frame() {
    assert!(matches!(
        RecordingReader::new(&b"VREFREC0"[..]),
        Err(RecordError::BadMagic)
    ));
    assert!(matches!(
        RecordingReader::new(&b"VREF"[..]),
        Err(RecordError::BadMagic)
    ));

    let bytes = encode(&frames());
    let cut = &bytes[..bytes.len() - 3];
    let results: Vec<_> = RecordingReader::new(cut).unwrap().collect();
    assert!(results[0].is_ok() && results[1].is_ok());
    assert!(matches!(
        results[2],
        Err(RecordError::Truncated { frame: 2 })
    ));
    assert_eq!(results.len(), 3, "the stream ends at the first error");
    // Replay reads what is whole and says where it stopped.
    let read = vref_record::read_recording(cut).unwrap();
    assert_eq!(read.frames.len(), 2);
    let stop = read.cut.unwrap();
    assert_eq!((stop.frame, stop.length), (2, cut.len() as u64));
    let whole_two = encode(&frames()[..2]);
    assert_eq!(stop.readable, whole_two.len() as u64);
    // A cut at a frame's end looks like a whole file (the format has no
    // end mark); anywhere else it is reported.
    let all = frames();
    for at in 1..bytes.len() {
        let read = vref_record::read_recording(&bytes[..at]).unwrap();
        let n = read.frames.len();
        assert_eq!(read.frames, all[..n], "cut at {at}");
        let boundary = encode(&all[..n]).len() == at;
        assert_eq!(read.cut.is_none(), boundary, "cut at {at}");
    }

    let mut huge = b"VREFREC1".to_vec();
    huge.extend_from_slice(&u32::MAX.to_le_bytes());
    let first = RecordingReader::new(&huge[..]).unwrap().next().unwrap();
    assert!(matches!(
        first,
        Err(RecordError::FrameTooLarge { frame: 0, .. })
    ));

    let mut garbage = b"VREFREC1".to_vec();
    garbage.extend_from_slice(&3u32.to_le_bytes());
    garbage.extend_from_slice(&[9, 9, 9]);
    let first = RecordingReader::new(&garbage[..]).unwrap().next().unwrap();
    assert!(matches!(first, Err(RecordError::Decode { frame: 0, .. })));
}

/// `RecordedSnapshot` as `VREFREC1` files hold it: before the up vector.
#[derive(serde::Serialize)]
enum FrameV1 {
    Snapshot(SnapshotV1),
    Gesture(RecordedRay),
}

#[derive(serde::Serialize)]
struct SnapshotV1 {
    robot: bool,
    sequence: u64,
    timestamp_ns: u64,
    frame_name: String,
    feature_dim: u32,
    objects: Vec<RecordedObject>,
}

#[test]
fn a_first_version_file_is_read_its_snapshots_without_an_up_vector() {
    let old = [
        FrameV1::Snapshot(SnapshotV1 {
            robot: true,
            sequence: 4,
            timestamp_ns: 2_000,
            frame_name: "robot_camera".to_owned(),
            feature_dim: 1,
            objects: vec![RecordedObject {
                track_id: 3,
                position: [0.0, 0.1, 0.9],
                position_sigma: [0.0; 3],
                feature: vec![0.5],
            }],
        }),
        FrameV1::Gesture(RecordedRay {
            sequence: 2,
            timestamp_ns: 2_100,
            origin: [0.0; 3],
            direction: [0.0, 0.0, 1.0],
            cone_half_angle: 0.1,
            confidence: 1.0,
        }),
    ];
    let mut bytes = b"VREFREC1".to_vec();
    for frame in &old {
        let body = bincode::serde::encode_to_vec(frame, bincode::config::standard()).unwrap();
        bytes.extend_from_slice(&(body.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&body);
    }
    let back: Vec<Frame> = RecordingReader::new(&bytes[..])
        .unwrap()
        .map(Result::unwrap)
        .collect();
    let Frame::Snapshot(s) = &back[0] else {
        panic!("{back:?}")
    };
    assert_eq!((s.sequence, s.objects[0].track_id, s.up), (4, 3, None));
    assert!(matches!(&back[1], Frame::Gesture(r) if r.timestamp_ns == 2_100));
    // Read as the current version, the same bytes are not frames.
    bytes[..8].copy_from_slice(vref_record::MAGIC);
    let first = RecordingReader::new(&bytes[..]).unwrap().next().unwrap();
    assert!(first.is_err(), "{first:?}");
    // New files are the current version.
    assert!(encode(&frames()).starts_with(vref_record::MAGIC));
    assert_eq!(vref_record::MAGIC, b"VREFREC2");
}

proptest! {
    #[test]
    fn arbitrary_bytes_never_panic(tail in prop::collection::vec(any::<u8>(), 0..200)) {
        let mut bytes = b"VREFREC1".to_vec();
        bytes.extend_from_slice(&tail);
        if let Ok(reader) = RecordingReader::new(&bytes[..]) {
            for item in reader.take(100) {
                let _ = item;
            }
        }
    }
}
