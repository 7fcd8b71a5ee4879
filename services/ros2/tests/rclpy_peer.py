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


class Ctx:
    def __init__(self, **kw):
        self.__dict__.update(kw)


def robot_markers(m):
    return [k for k in m.markers if k.ns == "robot"]


def camera_scenario(c):
    """Markers, the service, malformed messages, a stopped matcher, CDR bytes."""
    import rclpy  # noqa: F401
    from rclpy.serialization import serialize_message, deserialize_message
    from visualization_msgs.msg import MarkerArray
    from std_srvs.srv import Trigger
    node, findings, frame, w, h = c.node, c.findings, c.frame, c.w, c.h
    rgb, depth, image, info, run_for = c.rgb, c.depth, c.image, c.info, c.run_for
    arrays, raw, trigger = c.arrays, c.raw, c.trigger
    colour_pub, depth_pub, info_pub = c.colour_pub, c.depth_pub, c.info_pub
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
    colour_pub.publish(image(now, "yuv422", rgb, w * 3))                # encoding
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
    # A matcher that stops answering (SIGSTOP) must not hold frames back:
    # markers keep coming at the frame rate, and the service says so.
    if c.args.matcher_pid:
        os.kill(c.args.matcher_pid, signal.SIGSTOP)
        try:
            mark = time.monotonic()
            future = trigger.call_async(Trigger.Request())
            run_for(3.0)
            stalled = len([1 for t, m in arrays if t > mark and robot_markers(m)])
            findings["arrays_in_3s_matcher_stopped"] = stalled
            check(stalled >= 15, f"only {stalled} marker arrays in 3 s at 10 frames/s "
                                 "while the matcher was stopped")
            run_for(5.0, until=future.done)
            if check(future.done(), "no service reply while the matcher was stopped"):
                reply = json.loads(future.result().message)
                findings["status_matcher_stopped"] = reply.get("status")
                check(not future.result().success and reply.get("status") == "error",
                      f"a stopped matcher should give status error, not {reply}")
        finally:
            os.kill(c.args.matcher_pid, signal.SIGCONT)

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



def pointing_scenario(c):
    """The same scene as both cameras (with the scene's own instance labels
    on both, so that both views hold the same objects under the same ids),
    and a pointing pose from the headset camera at one object: the matcher
    must answer ok with that object, and the answer, the referenced object
    and the headset pose (about the identity) must arrive over ROS 2."""
    import numpy as np
    from rclpy.qos import qos_profile_sensor_data, QoSProfile, ReliabilityPolicy, HistoryPolicy
    from rclpy.qos import DurabilityPolicy
    from sensor_msgs.msg import Image, CameraInfo
    from geometry_msgs.msg import PoseStamped, PointStamped
    from std_srvs.srv import Trigger
    node, findings, frame, w, h = c.node, c.findings, c.frame, c.w, c.h
    lab = np.frombuffer(c.labels, dtype="<u2").reshape(h, w)
    dep = np.frombuffer(c.depth, dtype="<u2").reshape(h, w)
    fx, fy, cx, cy = frame["fx"], frame["fy"], frame["cx"], frame["cy"]
    seen = {}
    for k in np.unique(lab):
        if k == 0:
            continue
        valid = (lab == k) & (dep > 0)
        if valid.sum() < 400:
            continue
        v, u = np.nonzero(valid)
        z = float(np.median(dep[valid])) / 1000.0
        d = np.array([(u.mean() - cx) / fx, (v.mean() - cy) / fy, 1.0])
        seen[int(k)] = (int(valid.sum()), d * z, d / np.linalg.norm(d))
    # Not the largest region (the table top in OSD); the object whose
    # direction is furthest from every other's, so that the cone holds it
    # alone.
    largest = max(seen, key=lambda k: seen[k][0])
    candidates = [k for k in seen if k != largest]
    def clearance(k):
        return min(math.acos(min(1.0, float(seen[k][2] @ seen[j][2]))) for j in seen if j != k)
    target = max(candidates, key=clearance)
    findings["objects"] = len(seen)
    findings["target"] = target
    findings["target_clearance_deg"] = round(math.degrees(clearance(target)), 1)
    d = seen[target][2]
    # The rotation taking the x axis to d: the pose's x axis is the ray.
    q = np.array([0.0, -d[2], d[1], 1.0 + d[0]])
    q /= np.linalg.norm(q)

    import rclpy
    from rclpy.node import Node
    sensor = qos_profile_sensor_data
    reliable = QoSProfile(reliability=ReliabilityPolicy.RELIABLE,
                          history=HistoryPolicy.KEEP_LAST, depth=10)

    def session(name, need_point, limit):
        """A fresh rclpy context and node (a new DDS participant, as a
        restarted peer is) publishing both cameras and the pointing pose
        until the service answers ok and the outputs arrived, or `limit`
        seconds; the context is shut down at the end."""
        from rclpy.context import Context
        from rclpy.executors import SingleThreadedExecutor
        context = Context()
        rclpy.init(context=context)
        node = Node(name, context=context)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        pubs = {
            "info": node.create_publisher(CameraInfo, "/camera/camera/color/camera_info", sensor),
            "colour": node.create_publisher(Image, "/camera/camera/color/image_raw", sensor),
            "depth": node.create_publisher(
                Image, "/camera/camera/aligned_depth_to_color/image_raw", sensor),
            "labels": node.create_publisher(Image, "/camera/camera/labels", sensor),
            "h_colour": node.create_publisher(Image, "/headset/color/image_raw", sensor),
            "h_depth": node.create_publisher(Image, "/headset/depth/image_raw", sensor),
            "h_info": node.create_publisher(CameraInfo, "/headset/color/camera_info", sensor),
            "h_labels": node.create_publisher(Image, "/headset/labels", sensor),
            "pointing": node.create_publisher(PoseStamped, "/headset/pointing", reliable),
        }
        points, poses = [], []
        # vref-ros2 keeps its latest referenced object for late subscribers.
        latched = QoSProfile(reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL,
                             history=HistoryPolicy.KEEP_LAST, depth=1)
        node.create_subscription(PointStamped, "/vref/referenced_object", points.append, latched)
        node.create_subscription(PoseStamped, "/vref/headset_pose", poses.append, reliable)
        trigger = node.create_client(Trigger, "/vref/latest_gesture")

        def both_cameras():
            stamp = node.get_clock().now().to_msg()
            for prefix in ["", "h_"]:
                pubs[prefix + "info"].publish(c.info(stamp, fx))
                pubs[prefix + "colour"].publish(c.image(stamp, "rgb8", c.rgb, w * 3))
                pubs[prefix + "depth"].publish(c.image(stamp, "16UC1", c.depth, w * 2))
                pubs[prefix + "labels"].publish(c.image(stamp, "16UC1", c.labels, w * 2))
            p = PoseStamped()
            p.header.stamp = stamp
            p.header.frame_id = "headset_camera"
            p.pose.orientation.x, p.pose.orientation.y = float(q[0]), float(q[1])
            p.pose.orientation.z, p.pose.orientation.w = float(q[2]), float(q[3])
            pubs["pointing"].publish(p)

        started = time.monotonic()
        end = started + limit
        next_frame = started
        future, future_at, replies = None, 0.0, []
        while time.monotonic() < end:
            now = time.monotonic()
            if now >= next_frame:
                both_cameras()
                next_frame += 0.1
            if future is None and trigger.service_is_ready() and now - future_at > 0.2:
                future, future_at = trigger.call_async(Trigger.Request()), now
            elif future is not None and future.done():
                replies.append(future.result())
                future = None
                if replies[-1].success and poses and (points or not need_point):
                    break
            elif future is not None and now - future_at > 5.0:
                # A request to a vref-ros2 that died is never answered.
                trigger.remove_pending_request(future)
                future = None
            executor.spin_once(timeout_sec=0.01)
        out = {"ok_after_s": round(time.monotonic() - started, 2), "replies": len(replies)}
        if check(replies, f"{name}: no service reply"):
            answer = json.loads(replies[-1].message)
            out["status"] = answer.get("status")
            check(replies[-1].success and answer.get("status") == "ok",
                  f"{name}: no ok answer within {limit} s (last: {replies[-1].message})")
            check(answer.get("robot_track_id") == target,
                  f"{name}: answered robot object {answer.get('robot_track_id')}, "
                  f"pointed at {target}")
        if need_point and check(points, f"{name}: no PointStamped on /vref/referenced_object"):
            p = points[-1]
            at = np.array([p.point.x, p.point.y, p.point.z])
            off = float(np.linalg.norm(at - seen[target][1]))
            out["point_off_surface_m"] = round(off, 3)
            check(p.header.frame_id == "camera_color_optical_frame",
                  f"{name}: point frame {p.header.frame_id}")
            # The front end puts the object's centre behind its visible surface.
            check(off < 0.15, f"{name}: referenced point {at} is {off:.3f} m from the surface")
        if check(poses, f"{name}: no PoseStamped on /vref/headset_pose"):
            t = poses[-1].pose.position
            shift = math.sqrt(t.x ** 2 + t.y ** 2 + t.z ** 2)
            out["headset_shift_m"] = round(shift, 4)
            check(shift < 0.05, f"{name}: the same view twice should put the headset at the "
                                f"robot camera, not {shift:.3f} m away")
        executor.shutdown()
        node.destroy_node()
        context.try_shutdown()
        return out

    findings["first"] = session("vref_test_peer", True, 45.0)
    # The peer restarts: a new context, so a new participant. vref-ros2 published this pair's
    # point before; it is kept for late subscribers (transient local).
    findings["peer_restarted"] = session("vref_test_peer_again", True, 30.0)
    # vref-ros2 crashes and is started again.
    c.restart_vref()
    findings["vref_ros2_restarted"] = session("vref_test_peer_third", True, 30.0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--vref-ros2", required=True)
    ap.add_argument("--config", required=True)
    ap.add_argument("--scene", required=True, help="folder with rgb.raw, depth.raw, frame.json")
    ap.add_argument("--log", required=True, help="where vref-ros2's log goes")
    ap.add_argument("--matcher-pid", type=int, help="the matcher, stopped for a while (SIGSTOP)")
    ap.add_argument("--pointing", action="store_true",
                    help="the headset scenario (pointing_scenario)")
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
    labels = None
    if args.pointing:
        with open(os.path.join(args.scene, "labels.raw"), "rb") as f:
            labels = f.read()
        assert len(labels) == w * h * 2

    log = open(args.log, "wb")
    env = dict(os.environ, RUST_LOG="info,rustdds=error,ros2_client=error")
    procs = [subprocess.Popen([args.vref_ros2, "--config", args.config],
                              stdout=log, stderr=subprocess.STDOUT, env=env)]

    def restart_vref():
        """SIGKILL, as a crash would, and start a new vref-ros2."""
        procs[0].kill()
        procs[0].wait(timeout=10)
        procs[0] = subprocess.Popen([args.vref_ros2, "--config", args.config],
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

        ctx = Ctx(node=node, findings=findings, frame=frame, w=w, h=h, rgb=rgb, depth=depth,
                  image=image, info=info, good_frame=good_frame, run_for=run_for,
                  arrays=arrays, raw=raw, trigger=trigger, colour_pub=colour_pub,
                  depth_pub=depth_pub, info_pub=info_pub, args=args, labels=labels,
                  restart_vref=restart_vref)
        if args.pointing:
            pointing_scenario(ctx)
        else:
            camera_scenario(ctx)
    finally:
        node.destroy_node()
        rclpy.shutdown()
        vref = procs[0]
        vref.send_signal(signal.SIGINT)
        try:
            code = vref.wait(timeout=10)
        except subprocess.TimeoutExpired:
            vref.kill()
            code = "killed"
        log.close()
    check(code == 0, f"vref-ros2 exit {code}")
    text = open(args.log, errors="replace").read()
    reasons = [] if args.pointing else [
        "encoding", "step", "data_size", "too_large", "intrinsics", "stamp_backwards"]
    for reason in reasons:
        check(f"reason=\"{reason}\"" in text or f"reason={reason}" in text,
              f"vref-ros2's log does not name {reason}")
    findings["failures"] = FAILURES
    print(json.dumps(findings), flush=True)
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
