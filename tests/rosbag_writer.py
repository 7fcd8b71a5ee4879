"""Writes a rosbag2 MCAP bag of one camera with the Python `rosbags`
package (pure Python, independent of vref): tests/rosbag.rs feeds it to
vref. The scene comes as the raw buffers tests/rosbag.rs writes
(rgb.raw: rgb8, depth.raw: u16 millimetres, labels.raw: u16, frame.json:
width, height, fx, fy, cx, cy).

Prints the path of the .mcap file.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

PREFIX = "/camera/camera"


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--out", required=True, help="bag folder (must not exist)")
    p.add_argument("--scene", required=True, help="folder with the raw buffers")
    p.add_argument("--frames", type=int, default=5)
    p.add_argument("--rate", type=float, default=10.0)
    p.add_argument("--colour-encoding", default="rgb8")
    p.add_argument("--depth-encoding", default="16UC1")
    p.add_argument("--labels", action="store_true", help="also the instance labels")
    p.add_argument("--prefix", default=PREFIX, help="topic prefix")
    p.add_argument("--no-info", action="store_true", help="leave CameraInfo out")
    p.add_argument(
        "--serialization", default="cdr", help="message encoding of the image topics"
    )
    a = p.parse_args()

    ts = get_typestore(Stores.ROS2_KILTED)
    Image = ts.types["sensor_msgs/msg/Image"]
    CameraInfo = ts.types["sensor_msgs/msg/CameraInfo"]
    Header = ts.types["std_msgs/msg/Header"]
    Time = ts.types["builtin_interfaces/msg/Time"]
    RegionOfInterest = ts.types["sensor_msgs/msg/RegionOfInterest"]

    scene = pathlib.Path(a.scene)
    frame = json.loads((scene / "frame.json").read_text())
    w, h = int(frame["width"]), int(frame["height"])
    rgb = np.frombuffer((scene / "rgb.raw").read_bytes(), dtype=np.uint8).reshape(h, w, 3)
    depth = np.frombuffer((scene / "depth.raw").read_bytes(), dtype="<u2").reshape(h, w)
    labels = np.frombuffer((scene / "labels.raw").read_bytes(), dtype="<u2").reshape(h, w)

    def header(ns: int, frame_id: str):
        return Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id=frame_id)

    def image(ns: int, encoding: str, pixels: np.ndarray, frame_id: str):
        data = np.ascontiguousarray(pixels).view(np.uint8).reshape(-1)
        return Image(
            header=header(ns, frame_id),
            height=h,
            width=w,
            encoding=encoding,
            is_bigendian=0,
            step=data.size // h,
            data=data,
        )

    if a.colour_encoding == "bgr8":
        colour_pixels = rgb[:, :, ::-1]
    elif a.colour_encoding == "rgba8":
        colour_pixels = np.concatenate([rgb, np.full((h, w, 1), 255, np.uint8)], axis=2)
    elif a.colour_encoding == "yuv422":
        # Two bytes a pixel; only the encoding's name matters to a refusal.
        colour_pixels = rgb[:, :, :2].copy()
    else:
        colour_pixels = rgb
    if a.depth_encoding == "32FC1":
        depth_pixels = depth.astype("<f4") / 1000.0
    else:
        depth_pixels = depth

    optical = "camera_color_optical_frame"
    topics = {
        "colour": f"{a.prefix}/color/image_raw",
        "depth": f"{a.prefix}/aligned_depth_to_color/image_raw",
        "info": f"{a.prefix}/color/camera_info",
        "labels": f"{a.prefix}/labels",
    }
    out = pathlib.Path(a.out)
    with Writer(out, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        conn = {}
        for key in ["colour", "depth"] + (["labels"] if a.labels else []):
            conn[key] = writer.add_connection(
                topics[key],
                Image.__msgtype__,
                typestore=ts,
                serialization_format=a.serialization,
            )
        if not a.no_info:
            conn["info"] = writer.add_connection(
                topics["info"], CameraInfo.__msgtype__, typestore=ts
            )
        start = 1_700_000_000 * 10**9
        for k in range(a.frames):
            ns = start + int(k * 1e9 / a.rate)
            msgs = [
                ("colour", image(ns, a.colour_encoding, colour_pixels, optical)),
                ("depth", image(ns, a.depth_encoding, depth_pixels, optical)),
            ]
            if a.labels:
                msgs.append(("labels", image(ns, "16UC1", labels, optical)))
            if not a.no_info:
                fx, fy, cx, cy = (float(frame[x]) for x in ("fx", "fy", "cx", "cy"))
                info = CameraInfo(
                    header=header(ns, optical),
                    height=h,
                    width=w,
                    distortion_model="plumb_bob",
                    d=np.zeros(5),
                    k=np.array([fx, 0, cx, 0, fy, cy, 0, 0, 1], dtype=np.float64),
                    r=np.eye(3).reshape(-1),
                    p=np.array([fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0], dtype=np.float64),
                    binning_x=0,
                    binning_y=0,
                    roi=RegionOfInterest(
                        x_offset=0, y_offset=0, height=0, width=0, do_rectify=False
                    ),
                )
                msgs.insert(0, ("info", info))
            for key, msg in msgs:
                writer.write(conn[key], ns, ts.serialize_cdr(msg, type(msg).__msgtype__))
    files = sorted(out.glob("*.mcap"))
    if len(files) != 1:
        print(f"expected one .mcap file in {out}, found {files}", file=sys.stderr)
        return 1
    print(files[0])
    return 0


if __name__ == "__main__":
    sys.exit(main())
