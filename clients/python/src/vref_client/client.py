"""Asks the matcher which robot object a person means."""

from __future__ import annotations

import ctypes
import struct
import time
from collections.abc import Callable, Sequence
from typing import Any, NamedTuple

import iceoryx2 as iox2
import numpy as np

from . import wire
from .errors import AnswerTimeout, MatcherNotRunning, QueryRefused, VrefError, WrongAnswer
from .services import Endpoint, IpcSettings, listener_wait, node_name, wrap
from .validate import U64_MAX, check_timeout, check_u64, ray_parts

#: Longest single sleep while waiting for an answer: the pending response
#: is re-checked at least this often, whatever the events say (as the Rust
#: client does).
POLL_S = 0.02
#: How long a request let go unanswered must find the matcher still serving
#: to count as refused rather than the matcher stopping (as the Rust client):
#: a matcher that stops lets its requests go a moment before it leaves.
REFUSED_AFTER_S = 0.1
#: Longest wait for a dead process's cleanup before a request let go
#: counts as refused anyway.
DEAD_CLEANUP_S = 2.0
#: Cone half-angle of ``by_ray`` when none is given, radians (as `vref query`).
DEFAULT_CONE = 0.1

_STATUS_NAMES = {code: name for name, code in wire.ANSWER_STATUSES.items()}
_ANSWER_SIZE = ctypes.sizeof(wire.ReferenceAnswer)
_QUERY_SIZE = ctypes.sizeof(wire.ReferenceQuery)
_POLL = iox2.Duration.from_secs_f64(POLL_S)
_INF = float("inf")
_HUMAN_OBJECT = wire.QUERY_KINDS["human_object"]
_LATEST_GESTURE = wire.QUERY_KINDS["latest_gesture"]
_RAY = wire.QUERY_KINDS["ray"]


class Alternative(NamedTuple):
    """A next-best robot object and the solution's share for it."""

    robot_track_id: int
    confidence: float


#: ``ReferenceAnswer`` as one ``struct`` unpack (little-endian, no padding:
#: the wire type has none); tests/test_client.py checks it against the
#: ctypes structure, which tests/test_layout.py checks against the layout.
ANSWER_STRUCT = struct.Struct("<9Q3f3ff3I" + "QfI" * wire.MAX_ALTERNATIVES + "II")
#: ``ReferenceQuery`` is packed as its two ids and the bytes of the rest
#: (``QUERY_REST``: ray, cone, kind, schema version, reserved), which are
#: constants for the queries without a ray; tests/test_client.py checks
#: both against the ctypes structure.
QUERY_REST = struct.Struct("<3f3ffIII")
_PACK_QUERY = struct.Struct(f"<2Q{QUERY_REST.size}s").pack_into
_UNPACK_ANSWER = ANSWER_STRUCT.unpack_from
_SCHEMA = wire.SCHEMA_VERSION
_HUMAN_OBJECT_REST = QUERY_REST.pack(0, 0, 0, 0, 0, 0, 0, _HUMAN_OBJECT, _SCHEMA, 0)
_LATEST_GESTURE_REST = QUERY_REST.pack(0, 0, 0, 0, 0, 0, 0, _LATEST_GESTURE, _SCHEMA, 0)
#: Chunk views kept per direction before the cache starts over: iceoryx2
#: reuses a fixed pool of chunks, so a few dozen addresses recur; only a
#: matcher restarted many times makes new ones.
_MAX_CHUNK_VIEWS = 1024
_new_tuple = tuple.__new__
_SOLVED = wire.ANSWER_FLAGS["solved"]
_HUMAN_POSITION = wire.ANSWER_FLAGS["human_position"]
_FROM_MOTION = wire.ANSWER_FLAGS["human_position_from_motion"]
_REFUSAL = wire.ANSWER_FLAGS["refusal"]
_REASON_NAMES = {code: name for name, code in wire.REJECT_REASONS.items()}


def _alternatives(v: tuple[Any, ...], count: int) -> tuple[Alternative, ...]:
    # tuple.__new__ directly: a NamedTuple's own __new__ is one more Python
    # call, and every Python step on the query path costs (docs/python.md).
    if count == 1:
        return (_new_tuple(Alternative, (v[19], v[20])),)
    if count == 2:
        return (_new_tuple(Alternative, (v[19], v[20])), _new_tuple(Alternative, (v[22], v[23])))
    return (
        _new_tuple(Alternative, (v[19], v[20])),
        _new_tuple(Alternative, (v[22], v[23])),
        _new_tuple(Alternative, (v[25], v[26])),
    )


def _answer(v: tuple[Any, ...]) -> Answer:
    """An answer from the values of ``ANSWER_STRUCT``."""
    # 0-8 the u64s, 9-11 position, 12-14 human_frame_position,
    # 15 confidence, 16 status, 17 alternative_count, 18 schema_version,
    # 19-27 alternatives (id, confidence, reserved), 28 flags, 29 refusal.
    flags = v[28]
    count = v[17]
    return _new_tuple(
        Answer,
        (
            _STATUS_NAMES.get(v[16], "bad_request"),
            v[0],
            v[1],
            v[2],
            v[9:12],
            v[15],
            _alternatives(v, count) if count else (),
            v[3],
            v[4],
            v[5],
            v[6],
            flags & _SOLVED != 0,
            v[7],
            v[8],
            v[12:15] if flags & _HUMAN_POSITION else None,
            flags & _FROM_MOTION != 0,
            flags,
            _REASON_NAMES.get(v[29]) if flags & _REFUSAL else None,
        ),
    )


def _chunk_view(views: dict[int, Any], address: int, size: int) -> Any:
    """``size`` bytes of shared memory at ``address`` as a ctypes array that
    ``struct`` packs into and unpacks from, made once per chunk."""
    if len(views) >= _MAX_CHUNK_VIEWS:
        views.clear()
    view = views[address] = (ctypes.c_char * size).from_address(address)
    return view


class Answer(NamedTuple):
    """The matcher's answer to one query (immutable).

    ``status`` is one of ``ok``, ``ambiguous`` (below the confidence
    threshold: see the alternatives), ``no_match`` (the referred object has
    no partner in the robot view, or no object is in the ray's cone),
    ``not_ready`` (a feed has not delivered yet, or no ray yet), ``stale``
    (a feed went silent: see the ages) or ``bad_request``.
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
    #: A real solve made the answering solution (else it was carried over
    #: because both snapshots held exactly the last solve's objects).
    #: Answers never wait for a solve.
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
    #: Why a ``stale`` or ``not_ready`` answer has nothing fresher: the
    #: matcher's reject reason (e.g. ``feature_dim_other_side``) of the
    #: latest snapshot it refused on a side with no newer accepted one;
    #: ``None`` when nothing was refused.
    refusal: str | None = None

    @property
    def ok(self) -> bool:
        """The status is ``ok``: a confident partner was found."""
        return self.status == "ok"

    @staticmethod
    def from_bytes(raw: bytes) -> Answer:
        """An answer from the bytes of a ``ReferenceAnswer``."""
        return _answer(ANSWER_STRUCT.unpack(raw))

    @staticmethod
    def from_wire(a: wire.ReferenceAnswer) -> Answer:
        """An answer from a ctypes ``ReferenceAnswer``."""
        return Answer.from_bytes(ctypes.string_at(ctypes.addressof(a), ctypes.sizeof(a)))


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

    _HANDLES = ("_reference", "_client", "_request_notifier", "_answers", "_loan")

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
        self._query = wire.ReferenceQuery(schema_version=wire.SCHEMA_VERSION)
        self._query_views: dict[int, Any] = {}
        self._answer_views: dict[int, Any] = {}
        loan = getattr(self._client, "__loan_uninit", None)
        if loan is not None and hasattr(iox2.RequestMutUninit, "__assume_init"):
            self._loan = loan
            self._send: Callable[[int, int, bytes], Any] = self._send_direct
        else:
            self._send = self._send_public

    # -- queries ---------------------------------------------------------

    def by_human_object(self, id: int, timeout: float = 1.0) -> Answer:
        """Which robot object is human object ``id``?"""
        # Plain ints and floats pass without a call; anything else is checked.
        human = id if type(id) is int and 0 <= id <= U64_MAX else check_u64("id", id)
        wait = timeout if type(timeout) is float and 0 < timeout < _INF else check_timeout(timeout)
        return self._ask(human, _HUMAN_OBJECT_REST, wait)

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
        (ox, oy, oz), (dx, dy, dz), cone = ray_parts(origin, direction, cone)
        wait = check_timeout(timeout)
        return self._ask(0, QUERY_REST.pack(ox, oy, oz, dx, dy, dz, cone, _RAY, _SCHEMA, 0), wait)

    def latest_gesture(self, timeout: float = 1.0) -> Answer:
        """Which robot object does the latest pointing gesture point at?"""
        wait = timeout if type(timeout) is float and 0 < timeout < _INF else check_timeout(timeout)
        return self._ask(0, _LATEST_GESTURE_REST, wait)

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

    def _let_go(self) -> VrefError:
        """Why the matcher let a request go unanswered: it stopped, or it
        still serves after ``REFUSED_AFTER_S`` and so refused this client."""
        start = time.monotonic()
        deadline = start + REFUSED_AFTER_S
        while self.matcher_running:
            now = time.monotonic()
            if now >= deadline:
                # A killed matcher's server stays listed until its cleanup
                # is done, and the cleanup lets its requests go first; on a
                # loaded machine the gap outlasts REFUSED_AFTER_S (as in the
                # Rust client). Waited out, at most DEAD_CLEANUP_S.
                if now - start >= DEAD_CLEANUP_S or not self._c.dead_nodes():
                    return QueryRefused(
                        "the matcher dropped the request unanswered: this client is over "
                        "[matcher] max_queries_per_client_hz"
                    )
                self._c.cleanup_dead_nodes()
                deadline = now + REFUSED_AFTER_S
            time.sleep(0.01)
        return MatcherNotRunning(self._not_running("any more: it stopped before answering"))

    def _not_running(self, when: str) -> str:
        return (
            f"no vref matcher serves {self._c.names.reference()} {when} "
            f"({self._c.where()}): start vref-matcher with the same [ipc] settings"
        )

    def _ask(self, human_id: int, rest: bytes, timeout: float) -> Answer:
        """Sends the query of ``human_id`` and the ``QUERY_REST`` bytes
        ``rest``, and waits for its answer."""
        # The query path is kept short: every Python step costs more than the
        # iceoryx2 round trip it wraps, the more so on a busy machine.
        if self._conn is None:
            raise VrefError("this ReferenceClient is closed")
        request_id = self._next_request
        self._next_request = request_id + 1
        try:
            pending = self._send(request_id, human_id, rest)
        except Exception as e:
            raise wrap("sending a reference query", e) from e
        try:
            if pending.number_of_server_connections == 0:
                raise MatcherNotRunning(self._not_running("now"))
            try:
                self._request_notifier.notify()
            except Exception as e:
                raise wrap("notifying the matcher of a query", e) from e
            return self._wait(pending, request_id, timeout)
        finally:
            pending.delete()

    def _send_public(self, request_id: int, human_id: int, rest: bytes) -> Any:
        """Loans a request, copies the query in, sends it (iceoryx2's API)."""
        _PACK_QUERY(self._query, 0, request_id, human_id, rest)
        return self._client.send_copy(self._query)

    def _send_direct(self, request_id: int, human_id: int, rest: bytes) -> Any:
        """``_send_public`` without the Python wrapper's checks, through the
        two native calls it makes (iceoryx2 0.10.0, pinned), the query packed
        straight into the loaned chunk; the checks it skips hold by
        construction (one request type, of the right size)."""
        request = self._loan()
        address = request.payload_ptr
        chunk = self._query_views.get(address)
        if chunk is None:
            chunk = _chunk_view(self._query_views, address, _QUERY_SIZE)
        _PACK_QUERY(chunk, 0, request_id, human_id, rest)
        return getattr(request, "__assume_init")().send()

    def _wait(self, pending: Any, request_id: int, timeout: float) -> Answer:
        # The clock is read only once an answer is not in at once (most are
        # in by the time notify() returns): the timeout counts from there.
        deadline = 0.0
        while True:
            try:
                response = pending.receive()
                if response is None and not pending.is_connected:
                    # The server let the request go: an answer sent just
                    # before that is in by now, or none will come.
                    response = pending.receive()
                    if response is None:
                        raise self._let_go()
            except VrefError:
                raise
            except Exception as e:
                raise wrap("receiving an answer", e) from e
            if response is not None:
                address = response.payload_ptr
                chunk = self._answer_views.get(address)
                if chunk is None:
                    chunk = _chunk_view(self._answer_views, address, _ANSWER_SIZE)
                values = _UNPACK_ANSWER(chunk)
                response.delete()
                answer = _answer(values)
                if answer.request_id != request_id:
                    raise WrongAnswer(
                        f"the answer echoed request {answer.request_id}, expected {request_id}"
                    )
                return answer
            if not deadline:
                deadline = time.monotonic() + timeout
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
                if left >= POLL_S:
                    self._answers.timed_wait(_POLL)
                else:
                    self._answers.timed_wait(listener_wait(left))
            except Exception as e:
                raise wrap("waiting for an answer", e) from e
