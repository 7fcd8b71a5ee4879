"""A perception stack written in Python: publishes both views of a small
table scene (six objects, the robot's view rotated and shifted) as
snapshots, and points at one object, so that the matcher has something to
match without the Rust feeds. Replace `detect()` with a segmenter's
output: track ids, positions in the camera frame, appearance features.

    python examples/table_feed.py [--config config/vref.toml] [--seconds 30]

Then `python examples/controller.py` (or `vref query --latest-gesture`)
answers with robot object 1000 - 7h for human object h.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from vref_client import IpcSettings, RayPublisher, SnapshotPublisher

HUMAN = np.array(
    [
        [-0.20, 0.10, 0.80],
        [0.00, 0.12, 0.95],
        [0.18, 0.08, 0.70],
        [0.25, 0.15, 1.05],
        [-0.10, 0.14, 1.15],
        [0.05, 0.05, 0.60],
    ],
    np.float32,
)


def detect(side: str, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Track ids, positions (n, 3) and features (n, 6) seen from ``side``."""
    h = np.arange(1, 7)
    features = np.full((6, 6), 0.05, np.float32)
    features[np.arange(6), h - 1] = 1.0
    wobble = np.float32(0.002 * np.sin(t))  # the objects are measured, not exact
    if side == "human":
        return h.astype(np.uint64), HUMAN + wobble, features
    x, y, z = HUMAN[:, 0], HUMAN[:, 1], HUMAN[:, 2]
    robot = np.stack([z - 0.9, y + 0.02, -x + 1.0], axis=1) + wobble
    return (1000 - 7 * h).astype(np.uint64), robot.astype(np.float32), features


def main() -> None:
    parser = argparse.ArgumentParser(description="Publish a table scene from Python.")
    parser.add_argument("--config", help="a vref.toml whose [ipc] says where the matcher is")
    parser.add_argument("--seconds", type=float, default=30.0)
    parser.add_argument("--rate", type=float, default=30.0, help="snapshots per second")
    parser.add_argument("--point-at", type=int, default=3, help="human object to point at")
    args = parser.parse_args()
    s = IpcSettings.from_toml(args.config) if args.config else IpcSettings()
    with (
        SnapshotPublisher("robot", s.namespace, s.prefix, s.root_path) as robot,
        SnapshotPublisher("human", s.namespace, s.prefix, s.root_path) as human,
        RayPublisher(s.namespace, s.prefix, s.root_path) as rays,
    ):
        end = time.monotonic() + args.seconds
        try:
            while time.monotonic() < end:
                t = time.monotonic()
                robot.publish(*detect("robot", t), position_sigma=0.01)
                human.publish(*detect("human", t), position_sigma=0.01)
                # The headset at the origin points at one object.
                rays.publish((0.0, 0.0, 0.0), HUMAN[args.point_at - 1], cone_half_angle=0.05)
                time.sleep(1.0 / args.rate)
        except KeyboardInterrupt:  # Ctrl-C: leave the with block, closing the ports
            pass


if __name__ == "__main__":
    main()
