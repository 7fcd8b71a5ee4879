#!/usr/bin/env python3
"""Reads an MCAP file that vref wrote with Python's `mcap` package (a
reader vref did not write): prints each channel's topic, message encoding,
schema name and encoding, and message count as counted by iterating the
messages, and checks them against the file's own statistics. With
`mcap-protobuf-support` installed it also decodes the Foxglove protobuf
channels from the schemas embedded in the file.

    pip install mcap mcap-protobuf-support
    python3 tools/check-mcap.py recording.mcap

Exit code 0 if the file reads and the counts agree, 1 otherwise.
"""

import sys
from collections import Counter

from mcap.reader import make_reader

# The mask outlines `vref view --images` writes, decoded when present.
ANNOTATIONS = ["/vref/robot/annotations", "/vref/human/annotations"]


def main(path: str) -> int:
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        counted = Counter()
        for _schema, channel, _message in reader.iter_messages():
            counted[channel.topic] += 1
    if summary is None or summary.statistics is None:
        print(f"{path}: no summary section")
        return 1
    failures = 0
    for channel_id, channel in sorted(summary.channels.items()):
        schema = summary.schemas.get(channel.schema_id)
        stated = summary.statistics.channel_message_counts.get(channel_id, 0)
        ok = stated == counted[channel.topic]
        failures += not ok
        print(
            f"{channel.topic}\t{channel.message_encoding}\t"
            f"{schema.name if schema else '-'}\t{schema.encoding if schema else '-'}\t"
            f"{counted[channel.topic]}{'' if ok else f' (statistics say {stated})'}"
        )
    try:
        from mcap_protobuf.decoder import DecoderFactory
    except ImportError:
        print("mcap-protobuf-support not installed: protobuf decoding skipped")
        return 1 if failures else 0
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        last = {}
        for _schema, channel, _message, decoded in reader.iter_decoded_messages(
            topics=["/vref/scene", "/tf", *ANNOTATIONS]
        ):
            last[channel.topic] = decoded
    scene = last.get("/vref/scene")
    if scene is not None:
        shapes = {
            e.id: len(e.spheres) + len(e.cubes) + len(e.lines) + len(e.arrows)
            for e in scene.entities
        }
        print(f"last foxglove.SceneUpdate decoded: primitives per entity {shapes}")
    tf = last.get("/tf")
    if tf is not None:
        frames = [f"{t.parent_frame_id}->{t.child_frame_id}" for t in tf.transforms]
        print(f"last foxglove.FrameTransforms decoded: {frames}")
    for topic in ANNOTATIONS:
        annotations = last.get(topic)
        if annotations is not None:
            points = sum(len(p.points) for p in annotations.points)
            print(
                f"last foxglove.ImageAnnotations on {topic} decoded: "
                f"{len(annotations.points)} outlines ({points} points), "
                f"{len(annotations.texts)} labels"
            )
    return 1 if failures else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
