"""A genuine ROS 2 peer (rclpy from the official wheels) for vref-ros2.

Run by services/ros2/tests/rclpy.rs inside a network namespace of its own
(only loopback up), never on the host network: it refuses to run where
any other interface exists. It starts vref-ros2 itself (so that both are
in that namespace), publishes a scene as the realsense driver would
(rgb8 colour, 16UC1 depth in mm, CameraInfo, one stamp per frame), and
checks:

1. MarkerArray messages arrive on /vref/markers with the robot's objects;
2. the Trigger service /vref/latest_gesture answers one line of JSON,
   success exactly when its status is "ok";
3. malformed messages (unsupported encoding, step and size mismatches,
   a 20000x20000 header, CameraInfo with fx 0 and NaN, stamps going
   backwards) are skipped, named in vref-ros2's log, and good frames keep
   flowing;
4. vref's CDR bytes of a MarkerArray (taken raw off the wire) equal
   rclpy.serialization.serialize_message of the same message.

The scene comes as raw files written by the Rust test (rgb.raw: rows of
RGB bytes; depth.raw: little-endian u16 millimetres; frame.json: size and
intrinsics). Prints one JSON line of findings; exits 1 on any failure.
Every wait is bounded.
"""

import argparse
import json
import math
import os
import signal
import subprocess
import sys
import time

FAILURES = []


def check(ok, what):
    if not ok:
        FAILURES.append(what)
        print(f"FAIL: {what}", file=sys.stderr, flush=True)
    return ok


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--vref-ros2", required=True)
    ap.add_argument("--config", required=True)
    ap.add_argument("--scene", required=True, help="folder with rgb.raw, depth.raw, frame.json")
    ap.add_argument("--log", required=True, help="where vref-ros2's log goes")
    args = ap.parse_args()

    # /proc/net/dev belongs to this process's network namespace (/sys/class/net
    # shows the namespace of whoever mounted /sys, the host's).
    with open("/proc/net/dev") as f:
        interfaces = sorted(line.split(":")[0].strip() for line in f.readlines()[2:])
    if interfaces != ["lo"]:
        print(f"refusing to run DDS outside a loopback-only namespace: {interfaces}",
              file=sys.stderr)
        return 3

    import rclpy
    from rclpy.node import Node
    from rclpy.qos import QoSProfile, ReliabilityPolicy, HistoryPolicy, DurabilityPolicy
    from rclpy.qos import qos_profile_sensor_data
    from rclpy.serialization import serialize_message, deserialize_message
    from sensor_msgs.msg import Image, CameraInfo
    from visualization_msgs.msg import MarkerArray
    from std_srvs.srv import Trigger

    with open(os.path.join(args.scene, "frame.json")) as f:
        frame = json.load(f)
    w, h = frame["width"], frame["height"]
    with open(os.path.join(args.scene, "rgb.raw"), "rb") as f:
        rgb = f.read()
    with open(os.path.join(args.scene, "depth.raw"), "rb") as f:
        depth = f.read()
    assert len(rgb) == w * h * 3 and len(depth) == w * h * 2

    log = open(args.log, "wb")
    env = dict(os.environ, RUST_LOG="info,rustdds=error,ros2_client=error")
    vref = subprocess.Popen([args.vref_ros2, "--config", args.config],
                            stdout=log, stderr=subprocess.STDOUT, env=env)
    findings = {}
    rclpy.init()
    node = Node("vref_test_camera")
    try:
        colour_pub = node.create_publisher(Image, "/camera/camera/color/image_raw",
                                           qos_profile_sensor_data)
        depth_pub = node.create_publisher(
            Image, "/camera/camera/aligned_depth_to_color/image_raw", qos_profile_sensor_data)
        info_pub = node.create_publisher(CameraInfo, "/camera/camera/color/camera_info",
                                         qos_profile_sensor_data)
        reliable = QoSProfile(reliability=ReliabilityPolicy.RELIABLE,
                              history=HistoryPolicy.KEEP_LAST, depth=10,
                              durability=DurabilityPolicy.VOLATILE)
        arrays = []
        node.create_subscription(MarkerArray, "/vref/markers",
                                 lambda m: arrays.append((time.monotonic(), m)), reliable)
        raw = []
        node.create_subscription(MarkerArray, "/vref/markers", lambda b: raw.append(b),
                                 reliable, raw=True)
        trigger = node.create_client(Trigger, "/vref/latest_gesture")

        def image(stamp, encoding, data, step, width=w, height=h):
            m = Image()
            m.header.stamp = stamp
            m.header.frame_id = "camera_color_optical_frame"
            m.width, m.height, m.encoding, m.step = width, height, encoding, step
            m.is_bigendian = 0
            m.data = data
            return m

        def info(stamp, fx):
            m = CameraInfo()
            m.header.stamp = stamp
            m.header.frame_id = "camera_color_optical_frame"
            m.width, m.height = w, h
            m.distortion_model = "plumb_bob"
            m.d = [0.0] * 5
            m.k = [fx, 0.0, frame["cx"], 0.0, frame["fy"], frame["cy"], 0.0, 0.0, 1.0]
            m.r = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
            m.p = [fx, 0.0, frame["cx"], 0.0, 0.0, frame["fy"], frame["cy"], 0.0,
                   0.0, 0.0, 1.0, 0.0]
            return m

        def good_frame():
            stamp = node.get_clock().now().to_msg()
            info_pub.publish(info(stamp, frame["fx"]))
            colour_pub.publish(image(stamp, "rgb8", rgb, w * 3))
            depth_pub.publish(image(stamp, "16UC1", depth, w * 2))

        def run_for(seconds, period=0.1, until=None):
            end = time.monotonic() + seconds
            next_frame = time.monotonic()
            while time.monotonic() < end:
                if time.monotonic() >= next_frame:
                    good_frame()
                    next_frame += period
                rclpy.spin_once(node, timeout_sec=0.01)
                if until is not None and until():
                    return True
            return until is None

        def robot_markers(m):
            return [k for k in m.markers if k.ns == "robot"]

        # 1. Markers with the robot's objects.
        started = time.monotonic()
        got = run_for(40.0, until=lambda: any(robot_markers(m) for _, m in arrays))
        findings["first_markers_s"] = round(time.monotonic() - started, 2)
        if check(got, "no MarkerArray with robot objects within 40 s"):
            last = [m for _, m in arrays if robot_markers(m)][-1]
            objects = robot_markers(last)
            findings["robot_objects"] = len(objects)
            check(objects[0].header.frame_id == "camera_color_optical_frame",
                  f"marker frame {objects[0].header.frame_id}")
            check(all(0.1 < k.pose.position.z < 5.0 for k in objects),
                  "robot objects should be 0.1-5 m in front of the camera")
            check(last.markers[0].action == 3, "the array should start with DELETEALL")

        # 2. The service.
        check(trigger.wait_for_service(timeout_sec=20.0), "service not available in 20 s")
        future = trigger.call_async(Trigger.Request())
        run_for(10.0, until=future.done)
        if check(future.done(), "no service reply within 10 s"):
            reply = future.result()
            check("\n" not in reply.message, "reply message must be one line")
            answer = json.loads(reply.message)
            findings["service_status"] = answer.get("status")
            check(reply.success == (answer.get("status") == "ok"),
                  f"success {reply.success} for status {answer.get('status')}")

        # 3. Malformed messages, then good frames again.
        now = node.get_clock().now().to_msg()
        colour_pub.publish(image(now, "rgba8", rgb, w * 3))                 # encoding
        colour_pub.publish(image(now, "rgb8", rgb, w * 3 - 1))             # step too short
        colour_pub.publish(image(now, "rgb8", rgb[: w * 3 * (h - 1)], w * 3))  # data too short
        colour_pub.publish(image(now, "rgb8", rgb[:30], 60000, 20000, 20000))  # 20000x20000
        time.sleep(0.05)
        info_pub.publish(info(now, 0.0))                                    # fx 0
        time.sleep(0.05)
        info_pub.publish(info(now, float("nan")))                           # fx NaN
        time.sleep(0.05)
        old = node.get_clock().now().to_msg()
        old.sec -= 100
        depth_pub.publish(image(old, "16UC1", depth, w * 2))                # backwards
        time.sleep(0.2)
        before = len([1 for _, m in arrays if robot_markers(m)])
        mark = time.monotonic()
        run_for(15.0, until=lambda: len([1 for t, m in arrays
                                         if t > mark and robot_markers(m)]) >= 3)
        after = len([1 for t, m in arrays if t > mark and robot_markers(m)])
        findings["arrays_after_malformed"] = after
        check(after >= 3, f"good frames stopped after the malformed ones ({before} before)")
        # 4. CDR: vref's bytes against rclpy's serialisation of the same message.
        if check(raw, "no raw MarkerArray bytes"):
            blob = raw[-1]
            again = serialize_message(deserialize_message(blob, MarkerArray))
            findings["cdr_bytes"] = len(blob)
            a, b = bytes(blob), bytes(again)
            first = next((i for i in range(min(len(a), len(b))) if a[i] != b[i]), min(len(a), len(b)))
            # RustDDS pads a payload to a multiple of 4 bytes with zeros and
            # does not declare them in the encapsulation options (rclpy reads
            # it all the same): equal up to those, and the count is reported.
            findings["cdr_trailing_padding"] = len(a) - len(b)
            same = a[:len(b)] == b and 0 <= len(a) - len(b) < 4 and not any(a[len(b):])
            check(same, f"CDR differs: vref {len(a)} bytes, rclpy {len(b)} bytes, from byte "
                          f"{first}: vref {a[first:first+8].hex()} rclpy {b[first:first+8].hex()}; "
                          f"heads {a[:8].hex()} {b[:8].hex()}")

    finally:
        node.destroy_node()
        rclpy.shutdown()
        vref.send_signal(signal.SIGINT)
        try:
            code = vref.wait(timeout=10)
        except subprocess.TimeoutExpired:
            vref.kill()
            code = "killed"
        log.close()
    check(code == 0, f"vref-ros2 exit {code}")
    text = open(args.log, errors="replace").read()
    for reason in ["encoding", "step", "data_size", "too_large", "intrinsics", "stamp_backwards"]:
        check(f"reason=\"{reason}\"" in text or f"reason={reason}" in text,
              f"vref-ros2's log does not name {reason}")
    findings["failures"] = FAILURES
    print(json.dumps(findings), flush=True)
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
