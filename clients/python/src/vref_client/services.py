"""vref's iceoryx2 services: names, settings, and how to open them.

This mirrors ``crates/vref-wire/src/ipc/services.rs``: every service is
opened with exactly the settings the Rust processes create it with (a
service created first with smaller settings makes a later open that asks
for more fail), and ``catalogue`` describes them in the form of
``docs/wire-layout.json`` so that ``tests/test_layout.py`` can compare the
two. A setting not named here is iceoryx2 0.10's default, on both sides.
"""

from __future__ import annotations

import ctypes
import os
import tomllib
from dataclasses import asdict, dataclass, field
from pathlib import Path
from types import TracebackType
from typing import Any, Final, TypeVar

import iceoryx2 as iox2

from . import wire
from .errors import IpcError, VrefError

#: Room per role for a dead predecessor's ports until cleanup.
PORTS_PER_ROLE: Final = 4
#: Event id sent when a notifier's process was found dead.
NOTIFIER_DEAD: Final = 7


@dataclass(frozen=True)
class IpcSettings:
    """Where and how vref's processes meet: the ``[ipc]`` section of
    ``config/vref.toml``. Every process of one system must agree on it."""

    namespace: str = "vref"
    prefix: str = "vref_"
    #: iceoryx2's root path; ``None``: iceoryx2's default (``/tmp/iceoryx2/``).
    root_path: str | None = None
    #: Objects a snapshot segment is first sized for (it grows when needed).
    initial_objects: int = 64
    max_clients: int = 16
    max_subscribers: int = 8
    #: iceoryx2's own configuration file; ``None``: iceoryx2's defaults.
    iceoryx2_config: str | None = None

    @staticmethod
    def from_toml(path: str | os.PathLike[str]) -> IpcSettings:
        """The ``[ipc]`` section of a vref configuration file (the keys the
        Rust services read; missing keys keep their defaults)."""
        with open(path, "rb") as f:
            ipc: dict[str, Any] = tomllib.load(f).get("ipc", {})
        known = {f.name for f in IpcSettings.__dataclass_fields__.values()}
        unknown = set(ipc) - known
        if unknown:
            raise ValueError(f"{path}: unknown [ipc] keys {sorted(unknown)}")
        values = dict(ipc)
        for key in ("root_path", "iceoryx2_config"):
            if values.get(key) is not None:
                values[key] = str(values[key])
        return IpcSettings(**values).checked()

    def checked(self) -> IpcSettings:
        """These settings, or a ``ValueError`` naming the first bad one."""
        if not self.namespace or self.namespace.startswith("/"):
            raise ValueError(f"namespace {self.namespace!r}: not a service name prefix")
        if not self.prefix or "/" in self.prefix:
            raise ValueError(f"prefix {self.prefix!r}: must be a non-empty file name")
        for name in ("initial_objects", "max_clients", "max_subscribers"):
            value = getattr(self, name)
            if not isinstance(value, int) or isinstance(value, bool) or value < 1:
                raise ValueError(f"{name} {value!r}: must be a positive integer")
        return self


@dataclass(frozen=True)
class PublishSubscribeQos:
    history_size: int
    subscriber_max_buffer_size: int
    #: ``None``: iceoryx2's default.
    subscriber_max_borrowed_samples: int | None
    enable_safe_overflow: bool
    max_publishers: int
    max_subscribers: int
    #: Nodes that may hold ports of the service at once.
    max_nodes: int

    def apply(self, builder: Any) -> Any:
        builder = (
            builder.history_size(self.history_size)
            .subscriber_max_buffer_size(self.subscriber_max_buffer_size)
            .enable_safe_overflow(self.enable_safe_overflow)
            .max_publishers(self.max_publishers)
            .max_subscribers(self.max_subscribers)
            .max_nodes(self.max_nodes)
        )
        if self.subscriber_max_borrowed_samples is not None:
            builder = builder.subscriber_max_borrowed_samples(self.subscriber_max_borrowed_samples)
        return builder


@dataclass(frozen=True)
class EventQos:
    max_notifiers: int
    max_listeners: int
    notifier_dead_event: int
    max_nodes: int


@dataclass(frozen=True)
class RequestResponseQos:
    max_clients: int
    max_servers: int
    max_active_requests_per_client: int
    max_response_buffer_size: int
    enable_safe_overflow_for_requests: bool
    enable_safe_overflow_for_responses: bool
    max_nodes: int


@dataclass(frozen=True)
class SlicePublisherQos:
    initial_max_slice_len: int
    allocation_strategy: str = "power_of_two"


def snapshot_qos(s: IpcSettings) -> PublishSubscribeQos:
    return PublishSubscribeQos(
        1, 1, 2, True, PORTS_PER_ROLE, s.max_subscribers, PORTS_PER_ROLE + s.max_subscribers
    )


def gesture_qos(s: IpcSettings) -> PublishSubscribeQos:
    return PublishSubscribeQos(
        1, 1, None, True, PORTS_PER_ROLE, s.max_subscribers, PORTS_PER_ROLE + s.max_subscribers
    )


def stats_qos(s: IpcSettings) -> PublishSubscribeQos:
    readers = s.max_subscribers + s.max_clients
    return PublishSubscribeQos(1, 1, None, True, PORTS_PER_ROLE, readers, PORTS_PER_ROLE + readers)


def decision_qos(s: IpcSettings) -> PublishSubscribeQos:
    readers = s.max_subscribers + s.max_clients
    return PublishSubscribeQos(1, 1, 2, True, PORTS_PER_ROLE, readers, PORTS_PER_ROLE + readers)


def slice_publisher_qos(s: IpcSettings) -> SlicePublisherQos:
    return SlicePublisherQos(max(s.initial_objects, 1))


def event_qos(s: IpcSettings) -> EventQos:
    notifiers = s.max_clients + PORTS_PER_ROLE
    listeners = max(s.max_subscribers, s.max_clients) + PORTS_PER_ROLE
    return EventQos(
        max_notifiers=notifiers,
        max_listeners=listeners,
        notifier_dead_event=NOTIFIER_DEAD,
        max_nodes=notifiers + listeners,
    )


def reference_qos(s: IpcSettings) -> RequestResponseQos:
    return RequestResponseQos(
        # Exactly [ipc] max_clients: the one past it is told so.
        max_clients=s.max_clients,
        max_servers=PORTS_PER_ROLE,
        max_active_requests_per_client=2,
        max_response_buffer_size=2,
        enable_safe_overflow_for_requests=True,
        enable_safe_overflow_for_responses=True,
        max_nodes=s.max_clients + PORTS_PER_ROLE,
    )


@dataclass(frozen=True)
class ServiceNames:
    """The names of vref's services under a namespace."""

    namespace: str

    @property
    def _ns(self) -> str:
        return self.namespace.rstrip("/")

    def snapshot(self, side: str) -> str:
        return f"{self._ns}/{side}/snapshot"

    def gesture(self) -> str:
        return f"{self._ns}/human/gesture"

    def reference(self) -> str:
        return f"{self._ns}/reference"

    def answers(self) -> str:
        return f"{self._ns}/reference/answers"

    def matcher_stats(self) -> str:
        return f"{self._ns}/matcher/stats"

    def decision(self) -> str:
        return f"{self._ns}/matcher/decision"

    @staticmethod
    def event_of(data_service: str) -> str:
        return f"{data_service}/event"


def _type_ref(t: type[ctypes.Structure], variant: str) -> dict[str, Any]:
    return {
        "type_name": wire.type_name_of(t),
        "variant": variant,
        "size": ctypes.sizeof(t),
        "align": ctypes.alignment(t),
    }


def catalogue(s: IpcSettings) -> list[dict[str, Any]]:
    """Every service as ``docs/wire-layout.json`` describes it (records
    ``service``, without the ``notifier`` and ``listener`` prose), from the
    settings this package opens them with."""
    names = ServiceNames(s.namespace)
    out: list[dict[str, Any]] = []

    def event(role: str, name: str) -> None:
        out.append({"role": role, "name": name, "pattern": "event", "qos": asdict(event_qos(s))})

    def pubsub(
        role: str,
        name: str,
        payload: dict[str, Any],
        header: dict[str, Any] | None,
        qos: PublishSubscribeQos,
        publisher: SlicePublisherQos | None,
        event_name: str | None,
    ) -> None:
        out.append(
            {
                "role": role,
                "name": name,
                "pattern": "publish_subscribe",
                "payload": payload,
                "user_header": header,
                "qos": asdict(qos),
                "publisher": asdict(publisher) if publisher else None,
                "event": event_name,
            }
        )

    for side in ("robot", "human"):
        name = names.snapshot(side)
        pubsub(
            f"{side}_snapshot",
            name,
            _type_ref(wire.ObjectEntry, "dynamic"),
            _type_ref(wire.SnapshotHeader, "fixed_size"),
            snapshot_qos(s),
            slice_publisher_qos(s),
            ServiceNames.event_of(name),
        )
        event(f"{side}_snapshot_event", ServiceNames.event_of(name))
    gesture = names.gesture()
    pubsub(
        "gesture",
        gesture,
        _type_ref(wire.PointingRay, "fixed_size"),
        None,
        gesture_qos(s),
        None,
        ServiceNames.event_of(gesture),
    )
    event("gesture_event", ServiceNames.event_of(gesture))
    reference = names.reference()
    out.append(
        {
            "role": "reference",
            "name": reference,
            "pattern": "request_response",
            "request": _type_ref(wire.ReferenceQuery, "fixed_size"),
            "response": _type_ref(wire.ReferenceAnswer, "fixed_size"),
            "qos": asdict(reference_qos(s)),
            "request_event": ServiceNames.event_of(reference),
            "response_event": names.answers(),
        }
    )
    event("request_event", ServiceNames.event_of(reference))
    event("answer_event", names.answers())
    pubsub(
        "matcher_stats",
        names.matcher_stats(),
        _type_ref(wire.MatcherStats, "fixed_size"),
        None,
        stats_qos(s),
        None,
        None,
    )
    decision = names.decision()
    pubsub(
        "decision",
        decision,
        _type_ref(wire.DecisionEntry, "dynamic"),
        _type_ref(wire.DecisionHeader, "fixed_size"),
        decision_qos(s),
        slice_publisher_qos(s),
        ServiceNames.event_of(decision),
    )
    event("decision_event", ServiceNames.event_of(decision))
    return out


def _hint(error: BaseException) -> str:
    text = repr(error)
    if "IncompatibleTypes" in text:
        return (
            " (the service's types differ from this package's, schema "
            f"{wire.SCHEMA_VERSION}: are the vref processes built from the same "
            "version as vref_client?)"
        )
    if "DoesNotSupport" in text or "IncompatibleMessagingPattern" in text:
        return (
            " (the service exists with other settings:"
            " do all processes use the same [ipc] settings?)"
        )
    if "ResourceCreationFailed" in text:
        return (
            " (listeners are Unix sockets under the root path, whose paths are limited to"
            " 107 bytes: use a shorter root_path)"
        )
    if "ServiceInCorruptedState" in text or "VersionMismatch" in text:
        return " (every process must use iceoryx2 0.10.0)"
    return ""


def wrap(what: str, error: BaseException) -> IpcError:
    """An ``IpcError`` saying what was being done, with iceoryx2's error."""
    return IpcError(f"{what}: {error!r}{_hint(error)}")


@dataclass
class Connection:
    """A node under the settings' root path and prefix, and the services
    opened through it. Ports must be released before the node."""

    settings: IpcSettings
    node: Any
    names: ServiceNames = field(init=False)

    def __post_init__(self) -> None:
        self.names = ServiceNames(self.settings.namespace)

    @staticmethod
    def create(settings: IpcSettings, node_name: str) -> Connection:
        settings.checked()
        try:
            if settings.iceoryx2_config is not None:
                config = iox2.config.from_file(iox2.FilePath.new(settings.iceoryx2_config))
            else:
                config = iox2.config.default()
            config.global_cfg.prefix = iox2.FileName.new(settings.prefix)
            if settings.root_path is not None:
                root = str(Path(settings.root_path))
                config.global_cfg.root_path = iox2.Path.new(root.rstrip("/") + "/")
            node = (
                iox2.NodeBuilder.new()
                .name(iox2.NodeName.new(node_name))
                .config(config)
                # Python keeps its own SIGINT handling (KeyboardInterrupt).
                .signal_handling_mode(iox2.SignalHandlingMode.Disabled)
                .create(iox2.ServiceType.Ipc)
            )
        except Exception as e:  # iceoryx2 raises its own exception types
            raise wrap(f"creating node {node_name!r} (prefix {settings.prefix!r})", e) from e
        return Connection(settings, node)

    def where(self) -> str:
        """The settings that decide which processes this one meets."""
        root = self.settings.root_path or "iceoryx2's default /tmp/iceoryx2/"
        return (
            f"namespace {self.settings.namespace!r}, prefix {self.settings.prefix!r}, "
            f"root path {root}"
        )

    def _builder(self, name: str) -> Any:
        return self.node.service_builder(iox2.ServiceName.new(name))

    def event(self, name: str) -> Any:
        qos = event_qos(self.settings)
        try:
            return (
                self._builder(name)
                .event()
                .max_notifiers(qos.max_notifiers)
                .max_listeners(qos.max_listeners)
                .notifier_dead_event(iox2.EventId.new(qos.notifier_dead_event))
                .max_nodes(qos.max_nodes)
                .open_or_create()
            )
        except Exception as e:
            raise wrap(f"opening event service {name}", e) from e

    def snapshot(self, side: str) -> tuple[Any, Any]:
        name = self.names.snapshot(side)
        try:
            builder = (
                self._builder(name)
                .publish_subscribe(iox2.Slice[wire.ObjectEntry])
                .user_header(wire.SnapshotHeader)
            )
            data = snapshot_qos(self.settings).apply(builder).open_or_create()
        except Exception as e:
            raise wrap(f"opening {name}", e) from e
        return data, self.event(ServiceNames.event_of(name))

    def gesture(self) -> tuple[Any, Any]:
        name = self.names.gesture()
        try:
            builder = self._builder(name).publish_subscribe(wire.PointingRay)
            data = gesture_qos(self.settings).apply(builder).open_or_create()
        except Exception as e:
            raise wrap(f"opening {name}", e) from e
        return data, self.event(ServiceNames.event_of(name))

    def reference(self) -> Any:
        name = self.names.reference()
        qos = reference_qos(self.settings)
        try:
            return (
                self._builder(name)
                .request_response(wire.ReferenceQuery, wire.ReferenceAnswer)
                .max_clients(qos.max_clients)
                .max_servers(qos.max_servers)
                .max_active_requests_per_client(qos.max_active_requests_per_client)
                .max_response_buffer_size(qos.max_response_buffer_size)
                .enable_safe_overflow_for_requests(qos.enable_safe_overflow_for_requests)
                .enable_safe_overflow_for_responses(qos.enable_safe_overflow_for_responses)
                .max_nodes(qos.max_nodes)
                .open_or_create()
            )
        except Exception as e:
            raise wrap(f"opening {name}", e) from e

    def stats(self) -> Any:
        name = self.names.matcher_stats()
        try:
            builder = self._builder(name).publish_subscribe(wire.MatcherStats)
            return stats_qos(self.settings).apply(builder).open_or_create()
        except Exception as e:
            raise wrap(f"opening {name}", e) from e

    def decision(self) -> tuple[Any, Any]:
        name = self.names.decision()
        try:
            builder = (
                self._builder(name)
                .publish_subscribe(iox2.Slice[wire.DecisionEntry])
                .user_header(wire.DecisionHeader)
            )
            data = decision_qos(self.settings).apply(builder).open_or_create()
        except Exception as e:
            raise wrap(f"opening {name}", e) from e
        return data, self.event(ServiceNames.event_of(name))

    def slice_publisher(self, data: Any) -> Any:
        qos = slice_publisher_qos(self.settings)
        return (
            data.publisher_builder()
            .initial_max_slice_len(qos.initial_max_slice_len)
            .allocation_strategy(iox2.AllocationStrategy.PowerOfTwo)
            .create()
        )

    def cleanup_dead_nodes(self) -> None:
        """Removes what crashed processes left (a dead matcher's server)."""
        try:
            self.node.try_cleanup_dead_nodes()
        except Exception:  # best effort: a failed cleanup changes nothing
            pass

    def dead_nodes(self) -> bool:
        """Whether some process died and is not yet cleaned up after (its
        server, if it had one, is still listed meanwhile)."""
        try:
            states = iox2.Node.list(iox2.ServiceType.Ipc, self.node.config)
        except Exception:  # unable to tell: nothing is known dead
            return False
        return any(isinstance(state, iox2.NodeState.Dead) for state in states)


_E = TypeVar("_E", bound="Endpoint")


class Endpoint:
    """Base of the package's classes: a connection and the ports opened
    through it, released in order by ``close`` (or leaving a ``with``
    block): ports first, then everything that keeps the node alive."""

    _ports: list[Any]
    _conn: Connection | None
    #: Attributes holding iceoryx2 objects, dropped by ``close``.
    _HANDLES: tuple[str, ...] = ()

    def _connect(self, settings: IpcSettings, name: str) -> Connection:
        self._ports = []
        self._conn = Connection.create(settings, name)
        return self._conn

    def _port(self, port: Any) -> Any:
        self._ports.append(port)
        return port

    @property
    def _c(self) -> Connection:
        if getattr(self, "_conn", None) is None:
            raise VrefError(f"this {type(self).__name__} is closed")
        assert self._conn is not None
        return self._conn

    def close(self) -> None:
        """Releases the ports and the node; unusable after."""
        for port in reversed(getattr(self, "_ports", [])):
            port.delete()
        self._ports = []
        for name in self._HANDLES:
            setattr(self, name, None)
        self._conn = None

    def __enter__(self: _E) -> _E:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


def node_name(kind: str) -> str:
    """A node name that tells which process this is."""
    return f"vref-py-{kind}-{os.getpid()}"


#: The shortest timeout a listener's ``timed_wait`` honours, seconds.
#: iceoryx2 0.10 waits on a socket receive timeout in whole microseconds,
#: and one that rounds to zero is no timeout: the wait blocks until a
#: notification comes, for ever if none does (as in the Rust client).
SHORTEST_LISTENER_WAIT_S = 1e-6


def listener_wait(seconds: float) -> iox2.Duration:
    """``seconds`` as a listener timeout, at least the shortest it honours."""
    if seconds < SHORTEST_LISTENER_WAIT_S:
        return iox2.Duration.from_micros(1)
    return iox2.Duration.from_secs_f64(seconds)
