"""Feeds written in Python: snapshots of one view and pointing rays,
written in place into loaned shared memory, with the matcher woken after
each. Session ids and sequence numbers behave as the Rust feeds' do: a new
random session per publisher, sequences 1, 2, 3, ... within it."""

from __future__ import annotations

import ctypes
import os
import time
from collections.abc import Sequence

import numpy as np

from . import validate, wire
from .services import Endpoint, IpcSettings, node_name, wrap

#: Frame names of the Rust feeds, the default of each side.
DEFAULT_FRAMES = {"robot": "robot_camera", "human": "headset_camera"}
_MASK = 2**64 - 1


def new_session() -> int:
    """A session id that differs between runs: the start time mixed with the
    process id through splitmix64's finaliser (as the Rust publishers)."""
    z = (time.time_ns() ^ (os.getpid() << 40)) & _MASK
    z = (z + 0x9E3779B97F4A7C15) & _MASK
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & _MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & _MASK
    return z ^ (z >> 31)


def _next_sequence(session: int, sequence: int) -> int:
    """The sequence number after ``sequence``, both checked: ctypes would
    wrap 2**64 to 0 silently, and the matcher take it as going back."""
    validate.check_u64("session", session)
    if validate.check_u64("sequence", sequence) == validate.U64_MAX:
        raise ValueError(
            "sequence: 2**64-1 was the session's last; start a new session"
            " (session = new_session(), sequence = 0)"
        )
    return sequence + 1


def _settings(
    namespace: str,
    prefix: str,
    root_path: str | None,
    initial_objects: int,
    max_clients: int,
    max_subscribers: int,
    iceoryx2_config: str | None,
) -> IpcSettings:
    return IpcSettings(
        namespace=namespace,
        prefix=prefix,
        root_path=None if root_path is None else str(root_path),
        initial_objects=initial_objects,
        max_clients=max_clients,
        max_subscribers=max_subscribers,
        iceoryx2_config=iceoryx2_config,
    ).checked()


class SnapshotPublisher(Endpoint):
    """Publishes one side's view (``"robot"``: the robot camera,
    ``"human"``: the headset) as snapshots the matcher takes in place.

    ``frame`` names the camera frame the positions are in (UTF-8, at most 32
    bytes); ``publish`` may override it per snapshot.
    """

    _HANDLES = ("_publisher", "_notifier")

    def __init__(
        self,
        side: str = "robot",
        namespace: str = "vref",
        prefix: str = "vref_",
        root_path: str | None = None,
        *,
        frame: str | None = None,
        initial_objects: int = 64,
        max_clients: int = 16,
        max_subscribers: int = 8,
        iceoryx2_config: str | None = None,
        node: str | None = None,
    ) -> None:
        if side not in wire.SIDE_CODES:
            raise ValueError(f"side: {side!r}, expected 'robot' or 'human'")
        self.side = side
        self.frame = DEFAULT_FRAMES[side] if frame is None else frame
        validate.frame_bytes(self.frame)
        settings = _settings(
            namespace,
            prefix,
            root_path,
            initial_objects,
            max_clients,
            max_subscribers,
            iceoryx2_config,
        )
        conn = self._connect(settings, node or node_name(f"{side}-feed"))
        data, event = conn.snapshot(side)
        try:
            self._publisher = self._port(conn.slice_publisher(data))
            self._notifier = self._port(event.notifier_builder().create())
        except Exception as e:
            raise wrap(f"creating the {side} snapshot publisher", e) from e
        self.session = new_session()
        self.sequence = 0

    @classmethod
    def from_config(
        cls, side: str, path: str, *, frame: str | None = None, node: str | None = None
    ) -> SnapshotPublisher:
        """A publisher with the ``[ipc]`` settings of a vref configuration file."""
        s = IpcSettings.from_toml(path)
        return cls(
            side,
            s.namespace,
            s.prefix,
            s.root_path,
            frame=frame,
            initial_objects=s.initial_objects,
            max_clients=s.max_clients,
            max_subscribers=s.max_subscribers,
            iceoryx2_config=s.iceoryx2_config,
            node=node,
        )

    def publish(
        self,
        track_ids: Sequence[int] | np.ndarray,
        positions: Sequence[Sequence[float]] | np.ndarray,
        features: Sequence[Sequence[float]] | np.ndarray | None,
        position_sigma: float | Sequence[float] | np.ndarray | None = None,
        frame: str | None = None,
        timestamp_ns: int | None = None,
        up: Sequence[float] | np.ndarray | None = None,
    ) -> int:
        """Publishes one snapshot and returns its sequence number.

        ``track_ids``: (n,) unique integers, stable across snapshots for the
        same object. ``positions``: (n, 3) metres in the camera frame (x
        right, y down, z forward). ``features``: (n, d) appearance features,
        d <= 64 and the same on both sides (``None``: no features).
        ``position_sigma``: one standard deviation per axis, metres, (n, 3)
        or anything that broadcasts to it (``None``: 0). ``timestamp_ns``:
        capture time since the Unix epoch (``None``: now). ``up``: which way
        is up (against gravity) in the camera frame, three finite numbers
        of any non-zero length (``None``: unknown).

        Every argument is checked before shared memory is touched: a bad one
        raises ``ValueError`` and nothing is published.
        """
        self._c  # noqa: B018 - raises once closed
        ids, pos, feat, sigma = validate.objects(track_ids, positions, features, position_sigma)
        name = validate.frame_bytes(self.frame if frame is None else frame)
        stamp = time.time_ns() if timestamp_ns is None else validate.check_timestamp(timestamp_ns)
        up_vector = validate.up_vector(up)
        n = int(ids.size)
        dim = int(feat.shape[1])
        sequence = _next_sequence(self.session, self.sequence)
        try:
            sample = self._publisher.loan_slice_uninit(n)
        except Exception as e:
            raise wrap(f"loaning a snapshot of {n} objects", e) from e
        header = wire.SnapshotHeader.from_address(sample.user_header_ptr)
        header.session = self.session
        header.sequence = sequence
        header.timestamp_ns = stamp
        header.schema_version = wire.SCHEMA_VERSION
        header.side = wire.SIDE_CODES[self.side]
        header.object_count = n
        header.feature_dim = dim
        ctypes.memset(ctypes.addressof(header.frame_name), 0, wire.FRAME_NAME_LEN)
        ctypes.memmove(ctypes.addressof(header.frame_name), name, len(name))
        if up_vector is None:
            header.up[:] = (0.0, 0.0, 0.0)
            header.flags = 0
        else:
            header.up[:] = up_vector
            header.flags = wire.SNAPSHOT_FLAGS["up"]
        if n:
            memory = (ctypes.c_uint8 * (n * wire.OBJECT_ENTRY_DTYPE.itemsize)).from_address(
                sample.payload_ptr
            )
            entries = np.frombuffer(memoryview(memory), dtype=wire.OBJECT_ENTRY_DTYPE, count=n)
            entries["track_id"] = ids
            entries["position"] = pos
            entries["position_sigma"] = sigma
            entries["feature"][:, :dim] = feat
            entries["feature"][:, dim:] = 0.0
            del entries, memory
        try:
            sample.assume_init().send()
            self._notifier.notify()
        except Exception as e:
            raise wrap("sending a snapshot", e) from e
        self.sequence = sequence
        return sequence


class RayPublisher(Endpoint):
    """Publishes pointing rays in the human view's frame (what a headset's
    gesture recogniser sees)."""

    _HANDLES = ("_publisher", "_notifier")

    def __init__(
        self,
        namespace: str = "vref",
        prefix: str = "vref_",
        root_path: str | None = None,
        *,
        max_clients: int = 16,
        max_subscribers: int = 8,
        iceoryx2_config: str | None = None,
        node: str | None = None,
    ) -> None:
        settings = _settings(
            namespace, prefix, root_path, 64, max_clients, max_subscribers, iceoryx2_config
        )
        conn = self._connect(settings, node or node_name("rays"))
        data, event = conn.gesture()
        try:
            self._publisher = self._port(data.publisher_builder().create())
            self._notifier = self._port(event.notifier_builder().create())
        except Exception as e:
            raise wrap("creating the ray publisher", e) from e
        self.session = new_session()
        self.sequence = 0

    @classmethod
    def from_config(cls, path: str, *, node: str | None = None) -> RayPublisher:
        """A publisher with the ``[ipc]`` settings of a vref configuration file."""
        s = IpcSettings.from_toml(path)
        return cls(
            s.namespace,
            s.prefix,
            s.root_path,
            max_clients=s.max_clients,
            max_subscribers=s.max_subscribers,
            iceoryx2_config=s.iceoryx2_config,
            node=node,
        )

    def publish(
        self,
        origin: Sequence[float] | np.ndarray,
        direction: Sequence[float] | np.ndarray,
        cone_half_angle: float = 0.1,
        confidence: float = 1.0,
        timestamp_ns: int | None = None,
    ) -> int:
        """Publishes one ray and returns its sequence number. ``direction``
        need not be unit length but must not be zero; objects within
        ``cone_half_angle`` (radians, in (0, pi/2]) are candidates;
        ``confidence`` is the recogniser's, in [0, 1]. Checked before
        anything is sent (``ValueError``)."""
        self._c  # noqa: B018 - raises once closed
        o, d, cone = validate.ray_parts(origin, direction, cone_half_angle)
        conf = validate.check_confidence(confidence)
        stamp = time.time_ns() if timestamp_ns is None else validate.check_timestamp(timestamp_ns)
        sequence = _next_sequence(self.session, self.sequence)
        try:
            sample = self._publisher.loan_uninit()
        except Exception as e:
            raise wrap("loaning a ray", e) from e
        ray = wire.PointingRay.from_address(sample.payload_ptr)
        ray.session = self.session
        ray.sequence = sequence
        ray.timestamp_ns = stamp
        ray.origin[:] = o
        ray.direction[:] = d
        ray.cone_half_angle = cone
        ray.confidence = conf
        ray.schema_version = wire.SCHEMA_VERSION
        ray.reserved = 0
        try:
            sample.assume_init().send()
            self._notifier.notify()
        except Exception as e:
            raise wrap("sending a ray", e) from e
        self.sequence = sequence
        return sequence
