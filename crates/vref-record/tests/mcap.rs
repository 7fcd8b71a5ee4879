//! MCAP recordings read back as frames: a file written here with the
//! `mcap` crate's own writer, as vref-view writes them (raw wire channels
//! beside others), and the format told by its first bytes.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::BTreeMap;
use std::io::Cursor;

use vref_record::{
    Frame, RecordError, RecordingWriter, WIRE_ENCODING, WIRE_SCHEMA_ENCODING, WireChannel,
    read_frames, read_recording,
};
use vref_wire::bytes::{WireBytes, put_sample, to_bytes};
use vref_wire::{MAX_FEATURE_DIM, ObjectEntry, PointingRay, SCHEMA_VERSION, SnapshotHeader};

fn header(sequence: u64, count: u32) -> SnapshotHeader {
    let mut frame_name = [0; 32];
    frame_name[..12].copy_from_slice(b"robot_camera");
    SnapshotHeader {
        session: 9,
        sequence,
        timestamp_ns: 1_000 * sequence,
        schema_version: SCHEMA_VERSION,
        side: 0,
        object_count: count,
        feature_dim: 2,
        frame_name,
        up: [0.0; 3],
        flags: 0,
    }
}

fn entry(id: u64) -> ObjectEntry {
    let mut feature = [0.0; MAX_FEATURE_DIM];
    feature[..2].copy_from_slice(&[0.5, 0.25]);
    ObjectEntry {
        track_id: id,
        position: [0.1, -0.2, 1.5],
        position_sigma: [0.01; 3],
        feature,
    }
}

fn ray() -> PointingRay {
    PointingRay {
        session: 3,
        sequence: 1,
        timestamp_ns: 1_500,
        origin: [0.0; 3],
        direction: [0.0, 0.1, 1.0],
        cone_half_angle: 0.1,
        confidence: 0.9,
        schema_version: 2,
        reserved: 0,
    }
}

#[test]
fn raw_wire_channels_read_back_as_the_frames_published() {
    let mut snapshot = Vec::new();
    // A count over the slice is kept as sent; the frame holds what the
    // slice carries.
    put_sample(&header(1, 3), &[entry(7), entry(8)], &mut snapshot);
    let mut upright = header(2, 1);
    upright.set_up(Some([0.0, -1.0, 0.0]));
    let mut with_up = Vec::new();
    put_sample(&upright, &[entry(9)], &mut with_up);
    let bytes = written(&[
        (WireChannel::RobotSnapshot, snapshot),
        (WireChannel::Gesture, to_bytes(&ray())),
        (WireChannel::HumanSnapshot, with_up),
    ]);
    let frames = read_frames(&bytes).unwrap();
    assert_eq!(frames.len(), 3, "{frames:?}");
    let Frame::Snapshot(h) = &frames[2] else {
        panic!("{frames:?}")
    };
    assert!(!h.robot);
    assert_eq!(h.up, Some([0.0, -1.0, 0.0]));
    let Frame::Snapshot(s) = &frames[0] else {
        panic!("{frames:?}")
    };
    assert!(s.robot);
    assert_eq!((s.sequence, s.timestamp_ns), (1, 1_000));
    assert_eq!(s.frame_name, "robot_camera");
    assert_eq!(s.objects.len(), 2);
    assert_eq!(s.objects[1].track_id, 8);
    assert_eq!(s.objects[1].feature, [0.5, 0.25]);
    assert_eq!(s.up, None);
    let Frame::Gesture(r) = &frames[1] else {
        panic!("{frames:?}")
    };
    assert_eq!(r.direction, [0.0, 0.1, 1.0]);
}

/// Files of wire schema 2 (before the up vector) hold a 72-byte snapshot
/// header, and their channel's schema says which schema they are.
#[test]
fn a_schema_2_file_is_read_its_snapshots_without_an_up_vector() {
    let old_header = |h: &SnapshotHeader| {
        let mut bytes = Vec::new();
        put_sample(h, &[entry(7), entry(8)], &mut bytes);
        // Today's header is schema 2's plus the up vector and flags at its
        // end.
        bytes.drain(72..SnapshotHeader::SIZE);
        bytes
    };
    let mut h = header(5, 2);
    h.schema_version = 2;
    let layout = |c: WireChannel| {
        c.layout()
            .replacen(&format!("schema {SCHEMA_VERSION}"), "schema 2", 1)
    };
    let bytes = written_with(&[(WireChannel::HumanSnapshot, old_header(&h))], layout);
    let frames = read_frames(&bytes).unwrap();
    let [Frame::Snapshot(s)] = frames.as_slice() else {
        panic!("{frames:?}")
    };
    assert_eq!((s.robot, s.sequence, s.up), (false, 5, None));
    assert_eq!(s.frame_name, "robot_camera");
    assert_eq!(
        s.objects.iter().map(|o| o.track_id).collect::<Vec<_>>(),
        [7, 8]
    );
    // The same bytes under today's schema are the wrong length.
    let bytes = written(&[(WireChannel::HumanSnapshot, old_header(&h))]);
    assert!(matches!(read_frames(&bytes), Err(RecordError::Wire { .. })));
    assert_eq!(
        WireChannel::schema_version_of(b"vref wire schema 12: x"),
        Some(12)
    );
    assert_eq!(WireChannel::schema_version_of(b"something else"), None);
}

#[test]
fn a_raw_message_of_the_wrong_length_names_its_channel() {
    let bytes = written(&[(WireChannel::Gesture, vec![0; 10])]);
    match read_frames(&bytes) {
        Err(RecordError::Wire { topic, .. }) => assert_eq!(topic, "/vref/wire/human/gesture"),
        other => panic!("{other:?}"),
    }
    // A file cut short is an MCAP error, not a panic.
    let whole = written(&[(WireChannel::Gesture, to_bytes(&ray()))]);
    assert!(read_frames(&whole[..whole.len() / 2]).is_err());
}

/// Issue 40, case 3: a recording cut at any byte (its recorder killed,
/// its disk full) replays every message of its complete chunks, says
/// where it stopped, and is never refused whole. vref-view writes as
/// here: zstd chunks built in memory and written whole.
#[test]
fn a_recording_cut_at_any_byte_reads_back_up_to_its_last_complete_chunk() {
    let messages: Vec<(WireChannel, Vec<u8>)> = (1..=12)
        .map(|k| {
            let mut r = ray();
            r.sequence = k;
            (WireChannel::Gesture, to_bytes(&r))
        })
        .collect();
    let options = mcap::WriteOptions::default()
        .compression(Some(mcap::Compression::Zstd))
        .disable_seeking(true)
        .chunk_size(Some(200));
    let whole = written_as(&messages, WireChannel::layout, options);
    let all = read_frames(&whole).unwrap();
    assert_eq!(all.len(), 12);
    let whole_read = read_recording(&whole).unwrap();
    assert_eq!((whole_read.frames.len(), whole_read.cut), (12, None));
    let mut last = 0;
    let mut counts = std::collections::BTreeSet::new();
    for at in 1..whole.len() {
        let read = read_recording(&whole[..at]).unwrap_or_else(|e| panic!("cut at {at}: {e}"));
        let n = read.frames.len();
        assert_eq!(read.frames, all[..n], "cut at {at}");
        assert!(n >= last, "cut at {at}: {n} frames after {last}");
        let cut = read
            .cut
            .unwrap_or_else(|| panic!("cut at {at} not reported"));
        assert_eq!((cut.length, cut.frame), (at as u64, n as u64));
        assert!(cut.readable <= at as u64);
        assert!(
            cut.to_string()
                .contains(&format!("first {} of {at} bytes", cut.readable))
        );
        last = n;
        counts.insert(n);
    }
    // Several chunks were complete at one cut or another, and every
    // message is read once its chunk is (the summary is all that a cut
    // near the end loses).
    assert!(counts.len() > 3, "{counts:?}");
    assert_eq!(last, 12);
    // The strict reader still refuses a cut file: only replay salvages.
    assert!(read_frames(&whole[..whole.len() - 1]).is_err());
}

#[test]
fn an_empty_file_is_called_empty() {
    assert!(matches!(read_recording(b""), Err(RecordError::Empty)));
    assert!(matches!(read_frames(b""), Err(RecordError::Empty)));
    assert!(RecordError::Empty.to_string().contains("empty"));
}

#[test]
fn vref_recordings_are_read_by_their_magic_too() {
    let mut w = RecordingWriter::new(Vec::new()).unwrap();
    let frame = Frame::Gesture(vref_record::RecordedRay::from_wire(&ray()));
    w.write(&frame).unwrap();
    let bytes = w.finish().unwrap();
    assert_eq!(read_frames(&bytes).unwrap(), vec![frame]);
    assert!(matches!(
        read_frames(b"neither"),
        Err(RecordError::BadMagic)
    ));
}

/// An MCAP file, written with the `mcap` crate's writer, holding the raw
/// wire channels and a JSON channel that a replay must skip: each message
/// is followed by a JSON one.
fn written(messages: &[(WireChannel, Vec<u8>)]) -> Vec<u8> {
    written_with(messages, WireChannel::layout)
}

/// As [`written`], with each raw channel's schema data from `layout`.
fn written_with(
    messages: &[(WireChannel, Vec<u8>)],
    layout: impl Fn(WireChannel) -> String,
) -> Vec<u8> {
    written_as(messages, layout, mcap::WriteOptions::default())
}

fn written_as(
    messages: &[(WireChannel, Vec<u8>)],
    layout: impl Fn(WireChannel) -> String,
    options: mcap::WriteOptions,
) -> Vec<u8> {
    let mut cursor = Cursor::new(Vec::new());
    {
        let mut writer = options.create(&mut cursor).unwrap();
        let mut ids = BTreeMap::new();
        for c in WireChannel::ALL {
            let schema = writer
                .add_schema(c.schema_name(), WIRE_SCHEMA_ENCODING, layout(c).as_bytes())
                .unwrap();
            let id = writer
                .add_channel(schema, c.topic(), WIRE_ENCODING, &BTreeMap::new())
                .unwrap();
            ids.insert(c.topic(), id);
        }
        let json = writer
            .add_channel(0, "/vref/answer", "json", &BTreeMap::new())
            .unwrap();
        let mut sequence = 0u32;
        for (channel, data) in messages {
            for (id, data) in [
                (ids[channel.topic()], data.as_slice()),
                (json, b"{}".as_slice()),
            ] {
                sequence += 1;
                let header = mcap::records::MessageHeader {
                    channel_id: id,
                    sequence,
                    log_time: u64::from(sequence),
                    publish_time: u64::from(sequence),
                };
                writer.write_to_known_channel(&header, data).unwrap();
            }
        }
        writer.finish().unwrap();
    }
    cursor.into_inner()
}
