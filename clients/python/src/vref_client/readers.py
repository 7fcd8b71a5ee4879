"""What the matcher publishes about itself: its statistics (every 200 ms)
and its decision after each solve."""

from __future__ import annotations

import ctypes
import time
from dataclasses import dataclass

import numpy as np

from . import wire
from .errors import VrefError
from .services import Endpoint, IpcSettings, listener_wait, node_name, wrap
from .validate import check_timeout

_STATUS_NAMES = {code: name for name, code in wire.ANSWER_STATUSES.items()}
_SIDE_NAMES = {code: name for name, code in wire.SIDE_CODES.items()}
_REASON_NAMES = {code: name for name, code in wire.REJECT_REASONS.items()}
#: How often ``StatsReader.wait`` looks (the stats service has no event).
STATS_POLL_S = 0.02


@dataclass(frozen=True)
class MatcherStats:
    """What the matcher has done since it started. Counters only grow while
    one matcher process lives; a restarted one starts from zero with a new
    ``pid`` and ``started_ns``."""

    started_ns: int
    taken_ns: int
    uptime_ms: int
    #: Snapshots taken from each side's service (``robot``, ``human``),
    #: valid or not.
    snapshots_received: dict[str, int]
    #: Of those, the ones that passed every check.
    snapshots_accepted: dict[str, int]
    #: Messages refused, by reason (every known reason; an index unknown to
    #: this package shows as ``reason_<index>`` when non-zero).
    rejected: dict[str, int]
    #: Queries answered, by status.
    answers: dict[str, int]
    solves: int
    rss_kb: int
    pid: int
    schema_version: int

    @property
    def rejected_total(self) -> int:
        return sum(self.rejected.values())

    @property
    def answered_total(self) -> int:
        return sum(self.answers.values())

    @staticmethod
    def from_wire(s: wire.MatcherStats) -> MatcherStats:
        rejected = {name: 0 for name in wire.REJECT_REASONS}
        for index, count in enumerate(s.rejected):
            if index in _REASON_NAMES:
                rejected[_REASON_NAMES[index]] = int(count)
            elif count:
                rejected[f"reason_{index}"] = int(count)
        answers = {name: 0 for name in wire.ANSWER_STATUSES}
        for index, count in enumerate(s.answers):
            if index in _STATUS_NAMES:
                answers[_STATUS_NAMES[index]] = int(count)
            elif count:
                answers[f"status_{index}"] = int(count)
        return MatcherStats(
            started_ns=int(s.started_ns),
            taken_ns=int(s.taken_ns),
            uptime_ms=int(s.uptime_ms),
            snapshots_received={_SIDE_NAMES[i]: int(s.snapshots_received[i]) for i in (0, 1)},
            snapshots_accepted={_SIDE_NAMES[i]: int(s.snapshots_accepted[i]) for i in (0, 1)},
            rejected=rejected,
            answers=answers,
            solves=int(s.solves),
            rss_kb=int(s.rss_kb),
            pid=int(s.pid),
            schema_version=int(s.schema_version),
        )


def _settings(
    namespace: str,
    prefix: str,
    root_path: str | None,
    max_clients: int,
    max_subscribers: int,
    iceoryx2_config: str | None,
) -> IpcSettings:
    return IpcSettings(
        namespace=namespace,
        prefix=prefix,
        root_path=None if root_path is None else str(root_path),
        max_clients=max_clients,
        max_subscribers=max_subscribers,
        iceoryx2_config=iceoryx2_config,
    ).checked()


class StatsReader(Endpoint):
    """Reads the matcher's statistics. The matcher need not be running yet;
    a restarted one is picked up. A new reader gets the last figures
    published at once."""

    _HANDLES = ("_subscriber",)

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
            namespace, prefix, root_path, max_clients, max_subscribers, iceoryx2_config
        )
        conn = self._connect(settings, node or node_name("stats"))
        data = conn.stats()
        try:
            self._subscriber = self._port(data.subscriber_builder().create())
        except Exception as e:
            raise wrap("creating the stats subscriber", e) from e

    @classmethod
    def from_config(cls, path: str, *, node: str | None = None) -> StatsReader:
        """A reader with the ``[ipc]`` settings of a vref configuration file."""
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

    def latest(self) -> MatcherStats | None:
        """The newest figures published since the last call, if any."""
        self._c  # noqa: B018 - raises once closed
        latest = None
        raw = wire.MatcherStats()
        while True:
            try:
                sample = self._subscriber.receive()
            except Exception as e:
                raise wrap("receiving matcher stats", e) from e
            if sample is None:
                break
            ctypes.memmove(ctypes.addressof(raw), sample.payload_ptr, ctypes.sizeof(raw))
            sample.delete()
            latest = MatcherStats.from_wire(raw)
        return latest

    def wait(self, timeout: float = 1.0) -> MatcherStats:
        """The next figures published (or not yet read), waiting up to
        ``timeout`` seconds: the service has no event, so this looks every
        20 ms, sleeping in between. Raises ``TimeoutError``."""
        wait = check_timeout(timeout)
        deadline = time.monotonic() + wait
        while True:
            stats = self.latest()
            if stats is not None:
                return stats
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(
                    f"no matcher stats within {wait:g} s ({self._c.where()}): "
                    "is vref-matcher running with the same [ipc] settings?"
                )
            time.sleep(min(STATS_POLL_S, left))


@dataclass(frozen=True)
class DecisionPair:
    """One human object's outcome in a decision."""

    human_track_id: int
    #: Its robot partner, ``None`` when it was given none.
    robot_track_id: int | None
    #: Probability that this outcome (a partner, or none) is right.
    confidence: float
    #: ``ok`` (matched), ``ambiguous`` (below the threshold) or ``no_match``.
    status: str
    #: The pair's squared residual under the decision's motion in units of
    #: the position errors both objects state (three degrees of freedom;
    #: an ``ok`` answer's is at most the matcher's ``fit_limit``); ``None``
    #: without a partner, a motion or errors stated on both sides.
    residual: float | None = None


@dataclass(frozen=True)
class Decision:
    """What the latest finished solve concluded about the whole scene."""

    robot_session: int
    robot_sequence: int
    robot_timestamp_ns: int
    human_session: int
    human_sequence: int
    human_timestamp_ns: int
    solved_ns: int
    solve_us: int
    solve_index: int
    #: Human camera frame to robot camera frame, ``q = R p + t``, when the
    #: method estimated it (``None`` otherwise).
    rotation: np.ndarray | None
    translation: np.ndarray | None
    method: str
    pairs: tuple[DecisionPair, ...]
    #: The median of the pairs' residuals (about 2.4 when the stated errors
    #: are honest and the motion right), ``None`` when no pair has one.
    residual_median: float | None = None

    @staticmethod
    def read(header: wire.DecisionHeader, entries: np.ndarray) -> Decision:
        """Copies a decision out of shared memory, checking its header's
        claims against what the sample carries (``VrefError`` otherwise)."""
        if header.schema_version != wire.SCHEMA_VERSION:
            raise VrefError(
                f"decision schema version {header.schema_version}, expected {wire.SCHEMA_VERSION}"
            )
        count = int(header.pair_count)
        if count > len(entries) or count > wire.MAX_DECISION_PAIRS:
            raise VrefError(f"decision counts {count} pairs but carries {len(entries)}")
        motion = bool(header.flags & wire.DECISION_HEADER_FLAGS["motion"])
        partner = wire.DECISION_ENTRY_FLAGS["partner"]
        tested = wire.DECISION_ENTRY_FLAGS["residual"]
        pairs = tuple(
            DecisionPair(
                human_track_id=int(e["human_track_id"]),
                robot_track_id=int(e["robot_track_id"]) if int(e["flags"]) & partner else None,
                confidence=float(e["confidence"]),
                status=_STATUS_NAMES.get(int(e["status"]), "bad_request"),
                residual=float(e["residual"]) if int(e["flags"]) & tested else None,
            )
            for e in entries[:count]
        )
        residuals = bool(header.flags & wire.DECISION_HEADER_FLAGS["residuals"])
        method = bytes(header.method).split(b"\0", 1)[0].decode("utf-8", "replace")
        return Decision(
            robot_session=int(header.robot_session),
            robot_sequence=int(header.robot_sequence),
            robot_timestamp_ns=int(header.robot_timestamp_ns),
            human_session=int(header.human_session),
            human_sequence=int(header.human_sequence),
            human_timestamp_ns=int(header.human_timestamp_ns),
            solved_ns=int(header.solved_ns),
            solve_us=int(header.solve_us),
            solve_index=int(header.solve_index),
            rotation=np.array(header.rotation, np.float64).reshape(3, 3) if motion else None,
            translation=np.array(header.translation, np.float64) if motion else None,
            method=method,
            pairs=pairs,
            residual_median=float(header.residual_median) if residuals else None,
        )


class DecisionReader(Endpoint):
    """Reads the matcher's decision after each solve (``wait`` sleeps on
    the decision event). The matcher need not be running yet."""

    _HANDLES = ("_subscriber", "_listener")

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
            namespace, prefix, root_path, max_clients, max_subscribers, iceoryx2_config
        )
        conn = self._connect(settings, node or node_name("decisions"))
        data, event = conn.decision()
        try:
            self._subscriber = self._port(data.subscriber_builder().create())
            self._listener = self._port(event.listener_builder().create())
        except Exception as e:
            raise wrap("creating the decision subscriber", e) from e

    @classmethod
    def from_config(cls, path: str, *, node: str | None = None) -> DecisionReader:
        """A reader with the ``[ipc]`` settings of a vref configuration file."""
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

    def latest(self) -> Decision | None:
        """The newest decision published since the last call, if any; a
        malformed one raises ``VrefError`` (and is consumed)."""
        self._c  # noqa: B018 - raises once closed
        newest = None
        while True:
            try:
                sample = self._subscriber.receive()
            except Exception as e:
                raise wrap("receiving a decision", e) from e
            if sample is None:
                break
            if newest is not None:
                newest.delete()
            newest = sample
        if newest is None:
            return None
        try:
            header = wire.DecisionHeader()
            ctypes.memmove(ctypes.addressof(header), newest.user_header_ptr, ctypes.sizeof(header))
            carried = int(newest.header.number_of_elements)
            size = carried * wire.DECISION_ENTRY_DTYPE.itemsize
            raw = ctypes.string_at(newest.payload_ptr, size) if carried else b""
            entries = np.frombuffer(raw, dtype=wire.DECISION_ENTRY_DTYPE, count=carried)
        finally:
            newest.delete()
        return Decision.read(header, entries)

    def wait(self, timeout: float = 1.0) -> Decision:
        """The next decision (or one not yet read), sleeping on the decision
        event up to ``timeout`` seconds. Raises ``TimeoutError``."""
        wait = check_timeout(timeout)
        deadline = time.monotonic() + wait
        while True:
            decision = self.latest()
            if decision is not None:
                return decision
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"no decision within {wait:g} s ({self._c.where()})")
            try:
                self._listener.timed_wait(listener_wait(min(left, 0.02)))
            except Exception as e:
                raise wrap("waiting for a decision", e) from e
