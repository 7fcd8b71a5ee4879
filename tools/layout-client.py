#!/usr/bin/env python3
"""A vref client made from the wire layout file alone.

    tools/layout-client.py [--layout docs/wire-layout.json] [--root-path DIR] [--rounds N]

It reads only the layout file (one JSON record per line, as `vref
wire-layout --json` prints it) and knows nothing else of vref: no import of
the vref_client package, no number copied from the Rust code. From the
layout it builds a ctypes structure per `type` record (following the
schema record's `type_grammar`, each field checked against its stated
offset and size), opens every service it uses by its `service` record
(name, pattern, type names, qos) under the schema record's
`iceoryx2_prefix` with the PyPI iceoryx2 package of the version the schema
names, and fills the fields as the schema's `field_rules` say. It then
publishes a robot and a human snapshot of a small table of its own (six
objects; the robot sees them turned and moved), a pointing ray, and asks
the matcher for each human object three ways (human_object, ray,
latest_gesture, the `QueryKind` codes), notifying the event services as
the schema's `event_rules` say, and reads the answers.

The iceoryx2 root path is the deployment's, not the wire's: --root-path
(default iceoryx2's own). Queries go --query-interval apart (default 2 ms,
well within the rate per client the field rules state). Prints one JSON
line: {"sent": N, "answers": M, "ok": K, "correct": C, "statuses": {...},
"wrong": [...]} where `ok` counts answers whose status is `ok`, `correct`
those of them naming the object the table says, and `wrong` lists the
others. Exit code 0 when it ran (whatever the
answers), 1 when something could not be opened or sent.
"""

from __future__ import annotations

import argparse
import ctypes
import json
import math
import os
import random
import re
import sys
import time
from pathlib import Path
from typing import Any

import iceoryx2 as iox2

BASE_TYPES: dict[str, Any] = {
    "u8": ctypes.c_uint8,
    "u16": ctypes.c_uint16,
    "u32": ctypes.c_uint32,
    "u64": ctypes.c_uint64,
    "i32": ctypes.c_int32,
    "i64": ctypes.c_int64,
    "f32": ctypes.c_float,
    "f64": ctypes.c_double,
}

# The client's own scene (not vref's): object h of the person's view, in the
# headset camera frame (metres), and the robot's view of it: turned a
# quarter about the vertical axis and moved, with a track id of its own.
HUMAN_TABLE: dict[int, tuple[float, float, float]] = {
    1: (-0.20, 0.10, 0.80),
    2: (0.00, 0.12, 0.95),
    3: (0.18, 0.08, 0.70),
    4: (0.25, 0.15, 1.05),
    5: (-0.10, 0.14, 1.15),
    6: (0.05, 0.05, 0.60),
}
FEATURE_LEN = 6


def robot_id(h: int) -> int:
    return 500 + 11 * h


def robot_position(p: tuple[float, float, float]) -> tuple[float, float, float]:
    x, y, z = p
    return (z - 0.9, y + 0.02, -x + 1.0)


def feature(h: int) -> list[float]:
    return [1.0 if k == h - 1 else 0.05 for k in range(FEATURE_LEN)]


class LayoutError(Exception):
    """The layout file lacks or contradicts something this client needs."""


class Layout:
    """The records of a layout file, and ctypes structures built from them."""

    def __init__(self, path: Path) -> None:
        self.records = [json.loads(line) for line in path.read_text().splitlines() if line]
        schemas = self.of("schema")
        if len(schemas) != 1:
            raise LayoutError(f"{path}: {len(schemas)} schema records, expected 1")
        self.schema: dict[str, Any] = schemas[0]
        for key in ("schema_version", "iceoryx2", "iceoryx2_prefix", "type_grammar",
                    "event_rules", "field_rules", "constants"):
            if key not in self.schema:
                raise LayoutError(f"{path}: the schema record has no `{key}`")
        self.types: dict[str, Any] = {}
        pending = {t["name"]: t for t in self.of("type")}
        while pending:
            # A type may name another (`[Alternative; 3]`): build those first.
            ready = [n for n, t in pending.items() if not self._unbuilt(t, pending)]
            if not ready:
                raise LayoutError(f"types naming each other or unknown types: {sorted(pending)}")
            for name in ready:
                self.types[name] = self._build(pending.pop(name))

    def of(self, record: str) -> list[dict[str, Any]]:
        return [r for r in self.records if r.get("record") == record]

    def service(self, role: str) -> dict[str, Any]:
        found = [s for s in self.of("service") if s.get("role") == role]
        if len(found) != 1:
            raise LayoutError(f"{len(found)} services of role {role!r}")
        return found[0]

    def service_named(self, name: str) -> dict[str, Any]:
        found = [s for s in self.of("service") if s.get("name") == name]
        if len(found) != 1:
            raise LayoutError(f"{len(found)} services named {name!r}")
        return found[0]

    def code(self, codes: str, name: str) -> int:
        for c in self.of("codes"):
            if c["name"] == codes:
                for v in c["values"]:
                    if v["name"] == name:
                        return int(v["value"])
        raise LayoutError(f"no code {name!r} in {codes!r}")

    def code_name(self, codes: str, value: int) -> str:
        for c in self.of("codes"):
            if c["name"] == codes:
                for v in c["values"]:
                    if v["value"] == value:
                        return str(v["name"])
        return f"unknown({value})"

    def by_type_name(self, type_name: str) -> Any:
        for t in self.of("type"):
            if t["type_name"] == type_name:
                return self.types[t["name"]]
        raise LayoutError(f"no type record has type_name {type_name!r}")

    @staticmethod
    def _elements(ty: str) -> str:
        """The innermost element type of a field type (`[[T; N]; M]` -> T)."""
        while ty.startswith("["):
            m = re.fullmatch(r"\[(.+); (\d+)\]", ty)
            if m is None:
                raise LayoutError(f"field type {ty!r} does not follow the type grammar")
            ty = m.group(1)
        return ty

    def _unbuilt(self, t: dict[str, Any], pending: dict[str, Any]) -> bool:
        return any(
            self._elements(f["type"]) in pending and self._elements(f["type"]) != t["name"]
            for f in t["fields"]
        )

    def _ctype(self, ty: str) -> Any:
        m = re.fullmatch(r"\[(.+); (\d+)\]", ty)
        if m is not None:
            return self._ctype(m.group(1)) * int(m.group(2))
        if ty in BASE_TYPES:
            return BASE_TYPES[ty]
        if ty in self.types:
            return self.types[ty]
        raise LayoutError(f"field type {ty!r} is neither a base type nor a record")

    def _build(self, t: dict[str, Any]) -> Any:
        fields: list[tuple[str, Any]] = []
        at = 0
        for k, f in enumerate(t["fields"]):
            if f["offset"] > at:
                fields.append((f"_pad{k}", ctypes.c_uint8 * (f["offset"] - at)))
                at = f["offset"]
            if f["offset"] != at:
                raise LayoutError(f"{t['name']}.{f['name']}: offset {f['offset']} overlaps")
            ctype = self._ctype(f["type"])
            if ctypes.sizeof(ctype) != f["size"]:
                raise LayoutError(f"{t['name']}.{f['name']}: {f['type']} is not {f['size']} bytes")
            fields.append((f["name"], ctype))
            at += f["size"]
        if t["size"] > at:
            fields.append(("_pad_end", ctypes.c_uint8 * (t["size"] - at)))
        type_name = t["type_name"]
        cls = type(
            t["name"],
            (ctypes.Structure,),
            {"_fields_": fields, "type_name": staticmethod(lambda: type_name)},
        )
        for f in t["fields"]:
            if getattr(cls, f["name"]).offset != f["offset"]:
                raise LayoutError(f"{t['name']}.{f['name']}: C layout puts it elsewhere")
        if ctypes.sizeof(cls) != t["size"] or ctypes.alignment(cls) != t["align"]:
            raise LayoutError(
                f"{t['name']}: {ctypes.sizeof(cls)} bytes, align {ctypes.alignment(cls)};"
                f" the layout says {t['size']}, align {t['align']}"
            )
        return cls


def apply_qos(builder: Any, qos: dict[str, Any]) -> Any:
    """Each qos entry is the builder method of its name (iceoryx2's own)."""
    for key, value in qos.items():
        if value is None:
            continue  # iceoryx2's default
        if key == "notifier_dead_event":
            builder = builder.notifier_dead_event(iox2.EventId.new(value))
        else:
            builder = getattr(builder, key)(value)
    return builder


class Client:
    """The node and the ports this client uses, opened from the layout."""

    def __init__(self, layout: Layout, root_path: str | None) -> None:
        self.layout = layout
        config = iox2.config.default()
        config.global_cfg.prefix = iox2.FileName.new(layout.schema["iceoryx2_prefix"])
        if root_path is not None:
            config.global_cfg.root_path = iox2.Path.new(root_path.rstrip("/") + "/")
        self.node = (
            iox2.NodeBuilder.new()
            .name(iox2.NodeName.new(f"layout-client-{os.getpid()}"))
            .config(config)
            .signal_handling_mode(iox2.SignalHandlingMode.Disabled)
            .create(iox2.ServiceType.Ipc)
        )
        self.ports: list[Any] = []
        self.notifiers: dict[str, Any] = {}
        self.session = random.getrandbits(63) | 1
        self.sequences: dict[str, int] = {}
        #: Events to notify later (--defer-notify), else None.
        self.deferred: list[str] | None = None

    def port(self, p: Any) -> Any:
        self.ports.append(p)
        return p

    def close(self) -> None:
        for p in reversed(self.ports):
            p.delete()
        self.ports = []

    def event_service(self, name: str) -> Any:
        record = self.layout.service_named(name)
        if record["pattern"] != "event":
            raise LayoutError(f"{name} is not an event service")
        builder = self.node.service_builder(iox2.ServiceName.new(name)).event()
        return apply_qos(builder, record["qos"]).open_or_create()

    def notifier(self, name: str) -> Any:
        if name not in self.notifiers:
            self.notifiers[name] = self.port(self.event_service(name).notifier_builder().create())
        return self.notifiers[name]

    def listener(self, name: str) -> Any:
        return self.port(self.event_service(name).listener_builder().create())

    def publisher(self, role: str) -> tuple[Any, dict[str, Any]]:
        record = self.layout.service(role)
        if record["pattern"] != "publish_subscribe":
            raise LayoutError(f"{role} is not publish_subscribe")
        payload = self.layout.by_type_name(record["payload"]["type_name"])
        if record["payload"]["variant"] == "dynamic":
            payload = iox2.Slice[payload]
        builder = self.node.service_builder(iox2.ServiceName.new(record["name"]))
        builder = builder.publish_subscribe(payload)
        if record.get("user_header") is not None:
            builder = builder.user_header(
                self.layout.by_type_name(record["user_header"]["type_name"])
            )
        service = apply_qos(builder, record["qos"]).open_or_create()
        factory = service.publisher_builder()
        settings = record.get("publisher")
        if settings is not None:
            factory = factory.initial_max_slice_len(settings["initial_max_slice_len"])
            strategy = "".join(w.capitalize() for w in settings["allocation_strategy"].split("_"))
            factory = factory.allocation_strategy(getattr(iox2.AllocationStrategy, strategy))
        return self.port(factory.create()), record

    def next_sequence(self, role: str) -> int:
        self.sequences[role] = self.sequences.get(role, 0) + 1
        return self.sequences[role]

    def sent(self, record: dict[str, Any]) -> None:
        """Event rule: after each sample, notify the service `event` names
        (at once, or with --defer-notify when the next request is sent)."""
        if record.get("event"):
            if self.deferred is None:
                self.notifier(record["event"]).notify()
            else:
                self.deferred.append(record["event"])

    def flush(self) -> None:
        """The deferred notifications, in the order their samples went."""
        for name in self.deferred or []:
            self.notifier(name).notify()
        if self.deferred is not None:
            self.deferred = []


def fill_common(message: Any, layout: Layout) -> None:
    """Field rules every message shares."""
    names = [f[0] for f in message._fields_]
    if "schema_version" in names:
        message.schema_version = layout.schema["schema_version"]
    if "reserved" in names:
        message.reserved = 0


class Run:
    def __init__(self, layout: Layout, client: Client) -> None:
        self.layout = layout
        self.client = client
        self.snapshots = {
            side: client.publisher(f"{side}_snapshot") for side in ("robot", "human")
        }
        self.gesture = client.publisher("gesture")
        reference = layout.service("reference")
        self.reference_record = reference
        request = layout.by_type_name(reference["request"]["type_name"])
        response = layout.by_type_name(reference["response"]["type_name"])
        self.request_type = request
        self.response_type = response
        builder = client.node.service_builder(iox2.ServiceName.new(reference["name"]))
        service = apply_qos(builder.request_response(request, response), reference["qos"])
        self.reference = service.open_or_create()
        self.requester = client.port(self.reference.client_builder().create())
        self.answers_listener = client.listener(reference["response_event"])
        self.next_request = 1
        self.counts: dict[str, int] = {}
        self.sent = 0
        self.answered = 0
        self.ok = 0
        self.correct = 0
        self.wrong: list[dict[str, Any]] = []

    def publish_snapshot(self, side: str) -> None:
        publisher, record = self.snapshots[side]
        header_type = self.layout.by_type_name(record["user_header"]["type_name"])
        entry_type = self.layout.by_type_name(record["payload"]["type_name"])
        objects = sorted(HUMAN_TABLE)
        sample = publisher.loan_slice_uninit(len(objects))
        header = header_type.from_address(sample.user_header_ptr)
        ctypes.memset(ctypes.addressof(header), 0, ctypes.sizeof(header_type))
        fill_common(header, self.layout)
        header.session = self.client.session
        header.sequence = self.client.next_sequence(record["role"])
        header.timestamp_ns = time.time_ns()
        header.side = self.layout.code("SideCode", side)
        header.object_count = len(objects)
        header.feature_dim = FEATURE_LEN
        name = f"layout_client_{side}".encode()
        ctypes.memmove(ctypes.addressof(header.frame_name), name, len(name))
        # No up vector: zeros and no `up` flag (field rule).
        header.flags = 0
        entries = (entry_type * len(objects)).from_address(sample.payload_ptr)
        ctypes.memset(ctypes.addressof(entries), 0, ctypes.sizeof(entries))
        for e, h in zip(entries, objects):
            e.track_id = h if side == "human" else robot_id(h)
            p = HUMAN_TABLE[h] if side == "human" else robot_position(HUMAN_TABLE[h])
            e.position[:] = p
            e.position_sigma[:] = (0.0, 0.0, 0.0)
            e.feature[:FEATURE_LEN] = feature(h)
        sample.assume_init().send()
        self.client.sent(record)

    def publish_ray(self, h: int) -> None:
        publisher, record = self.gesture
        ray_type = self.layout.by_type_name(record["payload"]["type_name"])
        ray = ray_type()
        fill_common(ray, self.layout)
        ray.session = self.client.session
        ray.sequence = self.client.next_sequence(record["role"])
        ray.timestamp_ns = time.time_ns()
        ray.origin[:] = (0.0, 0.0, 0.0)
        ray.direction[:] = direction(HUMAN_TABLE[h])
        ray.cone_half_angle = 0.05
        ray.confidence = 1.0
        publisher.send_copy(ray)
        self.client.sent(record)

    def ask(self, kind: str, h: int, timeout_s: float) -> Any:
        """One query; its answer, or None when none came within `timeout_s`."""
        query = self.request_type()
        fill_common(query, self.layout)
        query.request_id = self.next_request
        self.next_request += 1
        query.kind = self.layout.code("QueryKind", kind)
        if kind == "human_object":
            query.human_object_id = h
        elif kind == "ray":
            query.ray_origin[:] = (0.0, 0.0, 0.0)
            query.ray_direction[:] = direction(HUMAN_TABLE[h])
            query.cone_half_angle = 0.05
        pending = self.requester.send_copy(query)
        try:
            self.client.flush()
            # Event rule: notify `request_event` after each request, and
            # listen on `response_event` for the answer.
            self.client.notifier(self.reference_record["request_event"]).notify()
            deadline = time.monotonic() + timeout_s
            while True:
                response = pending.receive()
                if response is not None:
                    answer = self.response_type.from_buffer_copy(
                        ctypes.string_at(response.payload_ptr, ctypes.sizeof(self.response_type))
                    )
                    response.delete()
                    if answer.request_id == query.request_id:
                        return answer
                    continue
                left = deadline - time.monotonic()
                if left <= 0:
                    return None
                self.answers_listener.timed_wait(iox2.Duration.from_secs_f64(min(left, 0.05)))
        finally:
            pending.delete()

    def status(self, answer: Any) -> str:
        return self.layout.code_name("AnswerStatus", int(answer.status))

    def wait_ready(self, timeout_s: float) -> None:
        """Publishes until an answer is something else than not_ready
        (the matcher has both views and a solution), at most `timeout_s`."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            self.publish_snapshot("robot")
            self.publish_snapshot("human")
            answer = self.ask("human_object", 1, 0.5)
            if answer is not None and self.status(answer) != "not_ready":
                return
            time.sleep(0.05)
        raise TimeoutError(f"the matcher gave no answer but not_ready within {timeout_s} s")

    def round(self, timeout_s: float, interval_s: float, kinds: list[str]) -> None:
        for h in sorted(HUMAN_TABLE):
            # Fresh snapshots for every object's queries: an answer resting
            # on an old one is `stale` (field rules, timestamp_ns).
            self.publish_snapshot("robot")
            self.publish_snapshot("human")
            # The ray first: two round trips later, when latest_gesture is
            # asked, the matcher has surely taken it.
            self.publish_ray(h)
            for kind in kinds:
                # Field rules: a client's queries beyond the matcher's rate
                # per client are dropped unanswered.
                time.sleep(interval_s)
                self.sent += 1
                answer = self.ask(kind, h, timeout_s)
                if answer is None:
                    self.counts["none"] = self.counts.get("none", 0) + 1
                    continue
                self.answered += 1
                status = self.status(answer)
                self.counts[status] = self.counts.get(status, 0) + 1
                if status == "ok":
                    self.ok += 1
                    if int(answer.robot_track_id) == robot_id(h):
                        self.correct += 1
                    else:
                        self.wrong.append(
                            {
                                "kind": kind,
                                "human_object": h,
                                "robot_track_id": int(answer.robot_track_id),
                                "expected": robot_id(h),
                                "ray_age_us": int(answer.ray_age_us),
                            }
                        )


def direction(p: tuple[float, float, float]) -> tuple[float, float, float]:
    n = math.sqrt(sum(c * c for c in p))
    return (p[0] / n, p[1] / n, p[2] / n)


def main() -> int:
    repo = Path(__file__).resolve().parents[1]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--layout", type=Path, default=repo / "docs" / "wire-layout.json")
    parser.add_argument("--root-path", default=None, help="iceoryx2's root path")
    parser.add_argument("--rounds", type=int, default=10)
    parser.add_argument("--answer-timeout", type=float, default=2.0)
    parser.add_argument("--ready-timeout", type=float, default=30.0)
    parser.add_argument(
        "--kinds",
        default="human_object,ray,latest_gesture",
        help="the QueryKind names asked for each object, in this order",
    )
    parser.add_argument(
        "--defer-notify",
        action="store_true",
        help="notify each object's snapshots and ray only once its first query is sent"
        " (still after each sample, as the event rules say, but all at once: the"
        " matcher then sees the query with the samples' events)",
    )
    parser.add_argument(
        "--query-interval",
        type=float,
        default=0.002,
        help="seconds between queries (0.002: a quarter of the matcher's default rate per client)",
    )
    args = parser.parse_args()
    layout = Layout(args.layout)
    kinds = args.kinds.split(",")
    for kind in kinds:
        layout.code("QueryKind", kind)  # a LayoutError for an unknown kind
    version = getattr(iox2, "__version__", None)
    if version is None:
        import importlib.metadata

        version = importlib.metadata.version("iceoryx2")
    if version != layout.schema["iceoryx2"]:
        print(f"iceoryx2 {version}, the layout wants {layout.schema['iceoryx2']}", file=sys.stderr)
        return 1
    client = Client(layout, args.root_path)
    defer = args.defer_notify
    try:
        run = Run(layout, client)
        run.wait_ready(args.ready_timeout)
        if defer:
            client.deferred = []
        for _ in range(args.rounds):
            run.round(args.answer_timeout, args.query_interval, kinds)
        print(
            json.dumps(
                {
                    "sent": run.sent,
                    "answers": run.answered,
                    "ok": run.ok,
                    "correct": run.correct,
                    "statuses": run.counts,
                    "wrong": run.wrong,
                }
            )
        )
    finally:
        client.close()
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (LayoutError, TimeoutError) as e:
        print(f"layout-client: {e}", file=sys.stderr)
        sys.exit(1)
