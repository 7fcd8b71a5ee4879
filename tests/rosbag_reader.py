"""Reads an MCAP file written by `vref record --ros2` with the Python
`rosbags` package (independent of vref) and, for each message, with
rclpy's own deserializer from the official ROS 2 wheels; prints one JSON
object with what it found, for tests/rosbag.rs to check. Exits 1 with the
reason on stderr when a message does not deserialize, or the two readers
disagree.
"""

from __future__ import annotations

import json
import math
import sys

from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore


def rclpy_types():
    """The rclpy message classes, or None where rclpy is not installed."""
    try:
        from geometry_msgs.msg import PointStamped, PoseStamped
        from rclpy.serialization import deserialize_message
        from visualization_msgs.msg import MarkerArray
    except ImportError:
        return None
    return deserialize_message, {
        "visualization_msgs/msg/MarkerArray": MarkerArray,
        "geometry_msgs/msg/PointStamped": PointStamped,
        "geometry_msgs/msg/PoseStamped": PoseStamped,
    }


def main() -> int:
    path = sys.argv[1]
    ts = get_typestore(Stores.ROS2_KILTED)
    rclpy = rclpy_types()
    topics: dict[str, dict] = {}
    namespaces: dict[str, int] = {}
    frames: set[str] = set()
    points = []
    poses = []
    with Reader(path) as reader:
        for conn in reader.connections:
            topics[conn.topic] = {
                "msgtype": conn.msgtype,
                "msgdef_format": conn.msgdef.format.name.lower(),
                "serialization_format": conn.ext.serialization_format,
                "durability": [q.durability.name.lower() for q in conn.ext.offered_qos_profiles],
                "reliability": [q.reliability.name.lower() for q in conn.ext.offered_qos_profiles],
                "count": 0,
            }
        for conn, _timestamp, raw in reader.messages():
            msg = ts.deserialize_cdr(raw, conn.msgtype)
            topics[conn.topic]["count"] += 1
            if rclpy is not None:
                deserialize, classes = rclpy
                other = deserialize(bytes(raw), classes[conn.msgtype])
            else:
                other = None
            if conn.msgtype == "visualization_msgs/msg/MarkerArray":
                for m in msg.markers:
                    namespaces[m.ns] = namespaces.get(m.ns, 0) + 1
                    frames.add(m.header.frame_id)
                if other is not None:
                    got = [(m.ns, m.id, m.type, m.action, m.pose.position.x) for m in other.markers]
                    want = [(m.ns, m.id, m.type, m.action, m.pose.position.x) for m in msg.markers]
                    if got != want:
                        print(f"rclpy and rosbags disagree on a MarkerArray: {got} {want}", file=sys.stderr)
                        return 1
            elif conn.msgtype == "geometry_msgs/msg/PointStamped":
                p = [msg.point.x, msg.point.y, msg.point.z]
                points.append({"frame_id": msg.header.frame_id, "point": p})
                if other is not None and [other.point.x, other.point.y, other.point.z] != p:
                    print("rclpy and rosbags disagree on a PointStamped", file=sys.stderr)
                    return 1
            elif conn.msgtype == "geometry_msgs/msg/PoseStamped":
                q = msg.pose.orientation
                poses.append(
                    {
                        "frame_id": msg.header.frame_id,
                        "position": [msg.pose.position.x, msg.pose.position.y, msg.pose.position.z],
                        "quaternion_norm": math.sqrt(q.x**2 + q.y**2 + q.z**2 + q.w**2),
                    }
                )
                if other is not None and other.pose.orientation.w != q.w:
                    print("rclpy and rosbags disagree on a PoseStamped", file=sys.stderr)
                    return 1
    print(
        json.dumps(
            {
                "topics": topics,
                "namespaces": namespaces,
                "marker_frames": sorted(frames),
                "points": points,
                "poses": poses,
                "rclpy": rclpy is not None,
            }
        )
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
