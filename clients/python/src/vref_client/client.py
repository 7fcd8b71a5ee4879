"""Asks the matcher which robot object a person means."""

from __future__ import annotations

import ctypes
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import iceoryx2 as iox2
import numpy as np

from . import wire
from .errors import AnswerTimeout, MatcherNotRunning, WrongAnswer
from .services import Endpoint, IpcSettings, node_name, wrap
from .validate import check_timeout, check_u64, ray_parts

#: Longest single sleep while waiting for an answer: the pending response
#: is re-checked at least this often, whatever the events say (as the Rust
#: client does).
POLL_S = 0.02
#: Cone half-angle of ``by_ray`` when none is given, radians (as `vref query`).
DEFAULT_CONE = 0.1

_STATUS_NAMES = {code: name for name, code in wire.ANSWER_STATUSES.items()}


@dataclass(frozen=True)
class Alternative:
    """A next-best robot object and the solution's share for it."""

    robot_track_id: int
    confidence: float


@dataclass(frozen=True)
class Answer:
    """The matcher's answer to one query.

    ``status`` is one of ``ok``, ``ambiguous`` (below the confidence
    threshold: see the alternatives), ``no_match`` (the referred object has
    no partner in the robot view), ``not_ready`` (a feed has not delivered
    yet), ``stale`` (a feed went silent: see the ages) or ``bad_request``.
    """

    status: str
    request_id: int
    #: The human-view object the query resolved to.
    human_object_id: int
    #: The robot object meant (0 when there is none).
    robot_track_id: int
    #: Its position in the robot camera frame, metres.
    position: tuple[float, float, float]
    #: Probability that the answer (a partner, or "no partner") is right.
    confidence: float
    alternatives: tuple[Alternative, ...]
    #: Sequence numbers of the snapshots the answering solution used.
    robot_sequence: int
    human_sequence: int
    #: Age of those snapshots when the answer was sent, microseconds.
    robot_age_us: int
    human_age_us: int
    #: The matcher solved the latest snapshots for this answer (else it came
    #: from the cached solution).
    solved: bool
    #: Time since the answering solution was finished, microseconds.
    solve_age_us: int
    #: Age of the stored pointing ray used (latest-gesture queries),
    #: microseconds; 0 when none was used.
    ray_age_us: int
    #: The answered object in the human view's frame, metres, when the
    #: matcher sent it (``None`` otherwise).
    human_frame_position: tuple[float, float, float] | None
    #: ``human_frame_position`` was mapped from the robot object through the
    #: estimated motion between the views (else it is the human object's own
    #: measured position).
    human_frame_position_from_motion: bool
    #: The raw ``flags`` bits (unknown bits are ignored).
    flags: int

    @property
    def ok(self) -> bool:
        """The status is ``ok``: a confident partner was found."""
        return self.status == "ok"

    @staticmethod
    def from_wire(a: wire.ReferenceAnswer) -> Answer:
        flags = int(a.flags)
        count = min(int(a.alternative_count), wire.MAX_ALTERNATIVES)
        has_human = bool(flags & wire.ANSWER_FLAGS["human_position"])
        return Answer(
            status=_STATUS_NAMES.get(int(a.status), "bad_request"),
            request_id=int(a.request_id),
            human_object_id=int(a.human_object_id),
            robot_track_id=int(a.robot_track_id),
            position=(float(a.position[0]), float(a.position[1]), float(a.position[2])),
            confidence=float(a.confidence),
            alternatives=tuple(
                Alternative(int(alt.robot_track_id), float(alt.confidence))
                for alt in a.alternatives[:count]
            ),
            robot_sequence=int(a.robot_sequence),
            human_sequence=int(a.human_sequence),
            robot_age_us=int(a.robot_age_us),
            human_age_us=int(a.human_age_us),
            solved=bool(flags & wire.ANSWER_FLAGS["solved"]),
            solve_age_us=int(a.solve_age_us),
            ray_age_us=int(a.ray_age_us),
            human_frame_position=(
                (
                    float(a.human_frame_position[0]),
                    float(a.human_frame_position[1]),
                    float(a.human_frame_position[2]),
                )
                if has_human
                else None
            ),
            human_frame_position_from_motion=bool(
                flags & wire.ANSWER_FLAGS["human_position_from_motion"]
            ),
            flags=flags,
        )


class ReferenceClient(Endpoint):
    """Asks the matcher which robot object a person means.

    Connects under ``namespace`` with iceoryx2's ``prefix`` and ``root_path``
    (the ``[ipc]`` settings of the vref processes; see ``from_config``). The
    matcher need not be running yet. Each query sends one request, wakes the
    matcher, and sleeps on the matcher's answer event until the answer
    arrives or ``timeout`` (seconds) passes. Not thread-safe: one client per
    thread.
    """

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
        settings = IpcSettings(
            namespace=namespace,
            prefix=prefix,
            root_path=None if root_path is None else str(root_path),
            max_clients=max_clients,
            max_subscribers=max_subscribers,
            iceoryx2_config=iceoryx2_config,
        )
        self._open(settings, node or node_name("client"))

    @classmethod
    def from_config(cls, path: str, *, node: str | None = None) -> ReferenceClient:
        """A client with the ``[ipc]`` settings of a vref configuration file."""
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

    _HANDLES = ("_reference", "_client", "_request_notifier", "_answers")

    def _open(self, settings: IpcSettings, name: str) -> None:
        conn = self._connect(settings, name)
        self._reference = conn.reference()
        requests = conn.event(conn.names.event_of(conn.names.reference()))
        answers = conn.event(conn.names.answers())
        try:
            self._client = self._port(self._reference.client_builder().create())
            self._request_notifier = self._port(requests.notifier_builder().create())
            self._answers = self._port(answers.listener_builder().create())
        except Exception as e:
            raise wrap("creating the reference client's ports", e) from e
        self._next_request = 1
        self._query = wire.ReferenceQuery()

    # -- queries ---------------------------------------------------------

    def by_human_object(self, id: int, timeout: float = 1.0) -> Answer:
        """Which robot object is human object ``id``?"""
        human = check_u64("id", id)
        wait = check_timeout(timeout)
        return self._ask(wire.QUERY_KINDS["human_object"], human, None, wait)

    def by_ray(
        self,
        origin: Sequence[float] | np.ndarray,
        direction: Sequence[float] | np.ndarray,
        cone_half_angle: float | None = None,
        timeout: float = 1.0,
    ) -> Answer:
        """Which robot object does this ray (human view's frame, metres;
        ``direction`` need not be unit length) point at? Objects within
        ``cone_half_angle`` radians of it are candidates (default 0.1)."""
        cone = DEFAULT_CONE if cone_half_angle is None else cone_half_angle
        ray = ray_parts(origin, direction, cone)
        wait = check_timeout(timeout)
        return self._ask(wire.QUERY_KINDS["ray"], 0, ray, wait)

    def latest_gesture(self, timeout: float = 1.0) -> Answer:
        """Which robot object does the latest pointing gesture point at?"""
        wait = check_timeout(timeout)
        return self._ask(wire.QUERY_KINDS["latest_gesture"], 0, None, wait)

    # -- the matcher -----------------------------------------------------

    @property
    def matcher_running(self) -> bool:
        """A matcher serves the reference service (a crashed one counts
        until some process cleans up after it)."""
        self._c  # noqa: B018 - raises once closed
        return int(self._reference.dynamic_config.number_of_servers) > 0

    def wait_for_matcher(self, timeout: float = 10.0) -> None:
        """Returns once a matcher serves the reference service; raises
        ``MatcherNotRunning`` after ``timeout`` seconds. Checks every 50 ms."""
        wait = check_timeout(timeout)
        self._c.cleanup_dead_nodes()
        deadline = time.monotonic() + wait
        while not self.matcher_running:
            left = deadline - time.monotonic()
            if left <= 0:
                raise MatcherNotRunning(self._not_running(f"within {wait:g} s"))
            time.sleep(min(0.05, left))

    def _not_running(self, when: str) -> str:
        return (
            f"no vref matcher serves {self._c.names.reference()} {when} "
            f"({self._c.where()}): start vref-matcher with the same [ipc] settings"
        )

    def _ask(
        self,
        kind: int,
        human_id: int,
        ray: tuple[tuple[float, float, float], tuple[float, float, float], float] | None,
        timeout: float,
    ) -> Answer:
        deadline = time.monotonic() + timeout
        if not self.matcher_running:
            raise MatcherNotRunning(self._not_running("now"))
        request_id = self._next_request
        self._next_request += 1
        q = self._query
        q.request_id = request_id
        q.human_object_id = human_id
        if ray is None:
            q.ray_origin[:] = (0.0, 0.0, 0.0)
            q.ray_direction[:] = (0.0, 0.0, 0.0)
            q.cone_half_angle = 0.0
        else:
            q.ray_origin[:] = ray[0]
            q.ray_direction[:] = ray[1]
            q.cone_half_angle = ray[2]
        q.kind = kind
        q.schema_version = wire.SCHEMA_VERSION
        try:
            pending = self._client.loan_uninit().write_payload(q).send()
            self._request_notifier.notify()
        except Exception as e:
            raise wrap("sending a reference query", e) from e
        try:
            return self._wait(pending, request_id, deadline, timeout)
        finally:
            pending.delete()

    def _wait(self, pending: Any, request_id: int, deadline: float, timeout: float) -> Answer:
        answer = wire.ReferenceAnswer()
        size = ctypes.sizeof(answer)
        while True:
            try:
                connected = bool(pending.is_connected)
                response = pending.receive()
            except Exception as e:
                raise wrap("receiving an answer", e) from e
            if response is not None:
                ctypes.memmove(ctypes.addressof(answer), response.payload_ptr, size)
                response.delete()
                if answer.request_id != request_id:
                    raise WrongAnswer(
                        f"the answer echoed request {answer.request_id}, expected {request_id}"
                    )
                return Answer.from_wire(answer)
            if not connected:
                raise MatcherNotRunning(self._not_running("any more: it stopped before answering"))
            left = deadline - time.monotonic()
            if left <= 0:
                # A matcher that died leaves its server registered until
                # someone cleans up; do it, so the error says what happened
                # and a restarted matcher is reached next time.
                self._c.cleanup_dead_nodes()
                if not self.matcher_running:
                    raise MatcherNotRunning(self._not_running("any more: its process is gone"))
                raise AnswerTimeout(f"no answer from the matcher within {timeout:g} s")
            try:
                self._answers.timed_wait(iox2.Duration.from_secs_f64(min(left, POLL_S)))
            except Exception as e:
                raise wrap("waiting for an answer", e) from e
