"""The ROS 2 side of `vref bench ros2` (written out and run by it, inside a
loopback-only network namespace): publishes one RGB-D frame over and over
as a camera driver would (rgb8, 16UC1, CameraInfo; each frame stamped
with the wall clock just before it is published), and measures, per
frame, when vref-ros2's MarkerArray showing it arrives (its robot spheres
carry the frame's stamp), and when a trivial rclpy relay node (--relay,
started by this script) passes the same frame's stamp back once it has
received that frame's colour and depth images: the bare DDS floor, in
the same run. Prints `warm` once the first marker array of a frame
arrived, then one JSON object at the end.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import threading
import time

import rclpy
from geometry_msgs.msg import PointStamped
from rclpy.node import Node
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
)
from sensor_msgs.msg import CameraInfo, Image
from visualization_msgs.msg import MarkerArray

COLOUR = "/camera/camera/color/image_raw"
DEPTH = "/camera/camera/aligned_depth_to_color/image_raw"
INFO = "/camera/camera/color/camera_info"
MARKERS = "/vref/markers"
RELAY = "/vref_bench/relay"

# A camera driver's images: reliable, keep the latest (a best-effort
# subscriber, as vref-ros2's, matches it and is served best effort).
IMAGES = QoSProfile(
    depth=1,
    history=HistoryPolicy.KEEP_LAST,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.VOLATILE,
)
RESULTS = QoSProfile(
    depth=10,
    history=HistoryPolicy.KEEP_LAST,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.VOLATILE,
)


def ns_of(stamp) -> int:
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def relay() -> int:
    """The floor's trivial node: the stamp of each frame whose colour and
    depth both arrived, back as a PointStamped."""
    rclpy.init()
    node = Node("vref_bench_relay")
    out = node.create_publisher(PointStamped, RELAY, RESULTS)
    # Stamps of recent images per stream; a frame goes back once both
    # of its images are in.
    seen = {"colour": [], "depth": []}

    def on(kind, other):
        def cb(msg: Image) -> None:
            stamp = ns_of(msg.header.stamp)
            if stamp in seen[other]:
                p = PointStamped()
                p.header = msg.header
                out.publish(p)
            else:
                seen[kind] = (seen[kind] + [stamp])[-8:]

        return cb

    # Best effort as vref-ros2 subscribes, with room for a few images, so
    # that Python's slowness does not count as the transport's loss.
    relay_qos = QoSProfile(
        depth=4,
        history=HistoryPolicy.KEEP_LAST,
        reliability=ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.VOLATILE,
    )
    node.create_subscription(Image, COLOUR, on("colour", "depth"), relay_qos)
    node.create_subscription(Image, DEPTH, on("depth", "colour"), relay_qos)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass
    return 0


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--frame", required=True, help="folder: rgb.raw, depth.raw, frame.json")
    p.add_argument("--seconds", type=float, required=True)
    p.add_argument("--rate", type=float, required=True)
    p.add_argument("--warmup-limit", type=float, default=60.0)
    p.add_argument("--relay", action="store_true", help="run as the relay node")
    a = p.parse_args()
    if a.relay:
        return relay()

    with open(os.path.join(a.frame, "frame.json")) as f:
        frame = json.load(f)
    w, h = int(frame["width"]), int(frame["height"])
    with open(os.path.join(a.frame, "rgb.raw"), "rb") as f:
        rgb = f.read()
    with open(os.path.join(a.frame, "depth.raw"), "rb") as f:
        depth = f.read()

    relay_proc = subprocess.Popen(
        [sys.executable, os.path.abspath(__file__), "--relay", "--frame", a.frame,
         "--seconds", "0", "--rate", "1"],
        stdin=subprocess.DEVNULL,
    )
    try:
        return measure(a, frame, w, h, rgb, depth)
    finally:
        relay_proc.terminate()
        try:
            relay_proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            relay_proc.kill()


def measure(a, frame, w, h, rgb, depth) -> int:
    rclpy.init()
    node = Node("vref_bench_camera")
    pub_colour = node.create_publisher(Image, COLOUR, IMAGES)
    pub_depth = node.create_publisher(Image, DEPTH, IMAGES)
    pub_info = node.create_publisher(CameraInfo, INFO, IMAGES)

    colour = Image(height=h, width=w, encoding="rgb8", is_bigendian=0, step=3 * w)
    colour.header.frame_id = "camera_color_optical_frame"
    colour.data = rgb
    dimg = Image(height=h, width=w, encoding="16UC1", is_bigendian=0, step=2 * w)
    dimg.header.frame_id = "camera_color_optical_frame"
    dimg.data = depth
    info = CameraInfo(height=h, width=w, distortion_model="plumb_bob")
    info.header.frame_id = "camera_color_optical_frame"
    fx, fy, cx, cy = (float(frame[k]) for k in ("fx", "fy", "cx", "cy"))
    info.k = [fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0]

    lock = threading.Lock()
    markers: dict[int, int] = {}
    relayed: dict[int, int] = {}

    def on_markers(msg: MarkerArray) -> None:
        now = time.time_ns()
        for m in msg.markers:
            if m.ns == "robot":
                stamp = ns_of(m.header.stamp)
                with lock:
                    markers.setdefault(stamp, now)
                return

    def on_relay(msg: PointStamped) -> None:
        now = time.time_ns()
        with lock:
            relayed.setdefault(ns_of(msg.header.stamp), now)

    node.create_subscription(MarkerArray, MARKERS, on_markers, RESULTS)
    node.create_subscription(PointStamped, RELAY, on_relay, RESULTS)
    spinner = threading.Thread(target=rclpy.spin, args=(node,), daemon=True)
    spinner.start()

    period = 1.0 / a.rate

    def publish() -> int:
        stamp = time.time_ns()
        for msg in (info, colour, dimg):
            msg.header.stamp.sec = stamp // 1_000_000_000
            msg.header.stamp.nanosec = stamp % 1_000_000_000
        pub_info.publish(info)
        pub_colour.publish(colour)
        pub_depth.publish(dimg)
        return stamp

    # Warm-up: discovery, vref-ros2's first frames, the relay's.
    deadline = time.monotonic() + a.warmup_limit
    next_at = time.monotonic()
    while True:
        with lock:
            ready = bool(markers) and bool(relayed)
        if ready:
            break
        if time.monotonic() > deadline:
            print(
                json.dumps({"error": f"no marker array or relay within {a.warmup_limit} s",
                            "markers": len(markers), "relayed": len(relayed)}),
                flush=True,
            )
            return 1
        publish()
        next_at += period
        time.sleep(max(0.0, next_at - time.monotonic()))
    print("warm", flush=True)

    published = []
    start = time.monotonic()
    next_at = start
    late = 0
    while time.monotonic() - start < a.seconds:
        published.append(publish())
        next_at += period
        wait = next_at - time.monotonic()
        if wait > 0:
            time.sleep(wait)
        else:
            late += 1
    # Late arrivals: a frame's markers within a second still count.
    time.sleep(1.0)
    with lock:
        out = {
            "published": published,
            "markers": [markers.get(s, 0) - s if s in markers else None for s in published],
            "relayed": [relayed.get(s, 0) - s if s in relayed else None for s in published],
            "publisher_late": late,
        }
    print(json.dumps(out), flush=True)
    rclpy.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
