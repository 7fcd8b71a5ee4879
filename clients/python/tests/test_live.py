"""vref_client against the real matcher and feeds (built binaries), each
test under its own iceoryx2 root path and prefix."""

from __future__ import annotations

import ctypes
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from conftest import HUMAN, System, eventually, feature, robot_id, robot_position
from vref_client import (
    AnswerTimeout,
    DecisionReader,
    MatcherNotRunning,
    MatcherStats,
    QueryRefused,
    RayPublisher,
    ReferenceClient,
    SnapshotPublisher,
    StatsReader,
    VrefError,
    wire,
)
from vref_client.services import Connection

READY_S = 30.0


def table(side: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The six-object table seen from ``side``: ids, positions, features."""
    hs = sorted(HUMAN)
    ids = np.array([h if side == "human" else robot_id(h) for h in hs], np.uint64)
    positions = np.array(
        [HUMAN[h] if side == "human" else robot_position(HUMAN[h]) for h in hs], np.float32
    )
    features = np.array([feature(h) for h in hs], np.float32)
    return ids, positions, features


def wait_ok(client: ReferenceClient, human: int = 1) -> None:
    def ok() -> bool | None:
        try:
            answer = client.by_human_object(human, timeout=0.5)
        except (MatcherNotRunning, TimeoutError):
            return None
        return True if answer.status == "ok" else None

    eventually(READY_S, "a first ok answer", ok)


def test_every_kind_of_query_is_answered_from_the_rust_feeds(system: System) -> None:
    source = system.dataset()
    system.start("matcher", "vref-matcher")
    system.start("perception", "vref-perception-feed", "--source", source, "--rate", "50")
    system.start("gesture", "vref-gesture-feed", "--source", source, "--rate", "50")
    with ReferenceClient(**system.ipc) as client:
        wait_ok(client)
        for h, p in HUMAN.items():
            a = client.by_human_object(h, timeout=2.0)
            assert (a.status, a.human_object_id, a.robot_track_id) == ("ok", h, robot_id(h))
            assert a.position == pytest.approx(robot_position(p), abs=1e-6)
            assert 0.0 <= a.confidence <= 1.0
            assert a.robot_sequence > 0 and a.human_sequence > 0
            assert len(a.alternatives) <= 3
            # Pointing from the headset's origin at the object resolves to it.
            r = client.by_ray((0.0, 0.0, 0.0), p, 0.05, timeout=2.0)
            assert (r.status, r.human_object_id, r.robot_track_id) == ("ok", h, robot_id(h))
        assert client.by_human_object(99, timeout=2.0).status == "bad_request"
        # iceoryx2's own send_copy, the fallback of the direct send.
        client._send = client._send_public
        assert client.by_human_object(2, timeout=2.0).robot_track_id == robot_id(2)
        # Pointing at nothing: no human object in the cone.
        assert client.by_ray((0, 0, 0), (0, -1, 0), 0.05, timeout=2.0).status == "no_match"
        # The dataset feed points at nothing; a Python headset bridge does.
        assert client.latest_gesture(timeout=2.0).status == "not_ready"
        with RayPublisher(**system.ipc) as rays:
            sequence = rays.publish((0.0, 0.0, 0.0), HUMAN[4], cone_half_angle=0.05)
            assert sequence == 1

            def pointed() -> tuple[str, int] | None:
                a = client.latest_gesture(timeout=2.0)
                return (a.status, a.robot_track_id) if a.status != "not_ready" else None

            assert eventually(5.0, "the ray taken", pointed) == ("ok", robot_id(4))


def wait_stats(
    reader: StatsReader, what: str, check: Callable[[MatcherStats], bool]
) -> MatcherStats:
    def poll() -> MatcherStats | None:
        stats = reader.latest()
        return stats if stats is not None and check(stats) else None

    return eventually(10.0, what, poll)


def test_snapshots_published_from_python_are_accepted_and_answered_from(system: System) -> None:
    system.start("matcher", "vref-matcher")
    with (
        StatsReader(**system.ipc) as stats,
        SnapshotPublisher("robot", **system.ipc) as robot,
        SnapshotPublisher("human", **system.ipc) as human,
        ReferenceClient(**system.ipc) as client,
    ):
        client.wait_for_matcher(timeout=READY_S)
        before = stats.wait(timeout=5.0)
        assert before.snapshots_received == {"robot": 0, "human": 0}
        assert client.by_human_object(1, timeout=2.0).status == "not_ready"

        ids, positions, features = table("robot")
        hids, hpositions, hfeatures = table("human")
        r1 = robot.publish(ids, positions, features, position_sigma=0.01)
        h1 = human.publish(hids, hpositions, hfeatures, position_sigma=[0.01, 0.01, 0.01])
        assert (r1, h1) == (1, 1)
        wait_stats(
            stats,
            "both sides' snapshots accepted",
            lambda s: s.snapshots_accepted == {"robot": 1, "human": 1},
        )
        # The objects move a little: the robot's second snapshot. (Latest
        # wins: a snapshot not yet taken when the next arrives is skipped.)
        assert robot.publish(ids, positions + np.float32(0.001), features, 0.01) == 2
        after = wait_stats(
            stats, "the second snapshot accepted", lambda s: s.snapshots_accepted["robot"] == 2
        )
        assert after.snapshots_received == {"robot": 2, "human": 1}
        assert after.rejected_total == 0

        for index, h in enumerate(sorted(HUMAN)):
            a = client.by_human_object(h, timeout=2.0)
            assert (a.status, a.robot_track_id) == ("ok", robot_id(h))
            # From our snapshots: their sequence numbers, our positions.
            assert (a.robot_sequence, a.human_sequence) == (2, 1)
            assert a.position == tuple(float(v) for v in positions[index] + np.float32(0.001))
        first = client.by_human_object(2, timeout=2.0)
        repeated = client.by_human_object(2, timeout=2.0)
        # Nothing new arrived: the same solution answers again, older.
        assert (repeated.robot_sequence, repeated.human_sequence) == (2, 1)
        assert repeated.solved and repeated.solve_age_us >= first.solve_age_us

        # A restarted publisher is a new session: its sequence 1 is taken.
        # (Open until the matcher took it: a publisher's samples go with it.)
        with SnapshotPublisher("robot", **system.ipc) as again:
            assert again.session != robot.session
            assert again.publish(ids, positions, features, position_sigma=0.01) == 1
            wait_stats(
                stats, "the new session accepted", lambda s: s.snapshots_accepted["robot"] == 3
            )
        solved = client.by_human_object(2, timeout=2.0)
        assert (solved.robot_sequence, solved.solved) == (1, True)


def test_an_up_vector_is_published_with_its_flag_and_a_bad_one_counted_as_bad_up(
    system: System,
) -> None:
    system.start("matcher", "vref-matcher")
    ids, positions, features = table("human")
    conn = Connection.create(system.settings, "up-reader")
    data, event = conn.snapshot("human")
    subscriber = data.subscriber_builder().create()
    raw = conn.slice_publisher(data)
    notifier = event.notifier_builder().create()

    def header() -> wire.SnapshotHeader:
        sample = eventually(5.0, "a snapshot", subscriber.receive)
        try:
            h = wire.SnapshotHeader()
            ctypes.memmove(ctypes.addressof(h), sample.user_header_ptr, ctypes.sizeof(h))
        finally:
            sample.delete()
        return h

    try:
        with (
            StatsReader(**system.ipc) as stats,
            SnapshotPublisher("human", **system.ipc) as human,
        ):
            stats.wait(timeout=READY_S)
            human.publish(ids, positions, features, up=(0.0, -2.0, 0.5))
            h = header()
            assert h.flags == wire.SNAPSHOT_FLAGS["up"]
            assert tuple(h.up) == (0.0, -2.0, 0.5)
            wait_stats(stats, "taken", lambda s: s.snapshots_accepted["human"] == 1)
            human.publish(ids, positions, features)
            h = header()
            assert (h.flags, tuple(h.up)) == (0, (0.0, 0.0, 0.0))
            wait_stats(stats, "taken again", lambda s: s.snapshots_accepted["human"] == 2)

            # Written by hand, past the publisher's checks: the matcher
            # refuses it under its own reason.
            sample = raw.loan_slice_uninit(len(ids))
            bad = wire.SnapshotHeader.from_address(sample.user_header_ptr)
            ctypes.memset(ctypes.addressof(bad), 0, ctypes.sizeof(bad))
            bad.session, bad.sequence, bad.timestamp_ns = 77, 1, time.time_ns()
            bad.schema_version = wire.SCHEMA_VERSION
            bad.side = wire.SIDE_CODES["human"]
            bad.object_count, bad.feature_dim = len(ids), features.shape[1]
            bad.flags = wire.SNAPSHOT_FLAGS["up"]
            memory = (ctypes.c_uint8 * (len(ids) * wire.OBJECT_ENTRY_DTYPE.itemsize)).from_address(
                sample.payload_ptr
            )
            entries = np.frombuffer(memoryview(memory), dtype=wire.OBJECT_ENTRY_DTYPE)
            entries["track_id"], entries["position"], entries["position_sigma"] = ids, positions, 0
            entries["feature"][:] = 0
            entries["feature"][:, : features.shape[1]] = features
            del entries, memory
            sample.assume_init().send()
            notifier.notify()
            refused = wait_stats(stats, "refused", lambda s: s.rejected_total > 0)
            assert refused.rejected["bad_up"] == 1, refused.rejected
            assert refused.snapshots_accepted["human"] == 2
    finally:
        notifier.delete()
        raw.delete()
        subscriber.delete()


def test_a_snapshot_larger_than_the_initial_segment_is_sent(system: System) -> None:
    system.start("matcher", "vref-matcher")
    n = 150  # more than [ipc] initial_objects (64): the segment must grow
    rng = np.random.default_rng(3)
    positions = rng.uniform(-1.0, 1.0, (n, 3)).astype(np.float32) + np.array([0, 0, 2], np.float32)
    features = rng.uniform(0.0, 1.0, (n, 8)).astype(np.float32)
    with StatsReader(**system.ipc) as stats, SnapshotPublisher("robot", **system.ipc) as robot:
        # The matcher reads a snapshot when woken for it: wait until it runs.
        stats.wait(timeout=READY_S)
        robot.publish(np.arange(10, 10 + n), positions, features)
        got = wait_stats(
            stats, "a large snapshot taken", lambda s: s.snapshots_received["robot"] > 0
        )
        assert got.snapshots_accepted["robot"] == 1, got.rejected


def test_a_malformed_publish_is_refused_before_it_reaches_the_wire(system: System) -> None:
    system.start("matcher", "vref-matcher")
    ids, positions, features = table("robot")
    with StatsReader(**system.ipc) as stats, SnapshotPublisher("robot", **system.ipc) as robot:
        stats.wait(timeout=READY_S)
        nan = positions.copy()
        nan[2, 1] = np.nan
        cases: dict[str, dict[str, Any]] = {
            "NaN position": {"positions": nan},
            "duplicate ids": {"track_ids": np.array([1, 2, 3, 4, 5, 1])},
            "too long features": {"features": np.ones((6, 65), np.float32)},
            "features of another count": {"features": features[:5]},
            "positions not (n, 3)": {"positions": positions[:, :2]},
            "negative sigma": {"position_sigma": -0.01},
            "infinite feature": {"features": np.where(features > 0.5, np.inf, features)},
            "frame over 32 bytes": {"frame": "x" * 33},
            "negative id": {"track_ids": np.array([-1, 2, 3, 4, 5, 6])},
            "zero up": {"up": (0.0, 0.0, 0.0)},
            "tiny up": {"up": (0.0, 1e-9, 0.0)},
            "NaN up": {"up": (np.nan, 1.0, 0.0)},
            "infinite up": {"up": (0.0, np.inf, 0.0)},
            "up beyond float32": {"up": (1e39, 0.0, 0.0)},
            "up of two": {"up": (0.0, 1.0)},
            "string positions": {"positions": [["0", "0", "1"]] * 6},
            "boolean features": {"features": [[True, False]] * 6},
            "lone surrogate frame": {"frame": "cam\udc80"},
        }
        for what, change in cases.items():
            args: dict[str, Any] = {"track_ids": ids, "positions": positions, "features": features}
            args.update(change)
            with pytest.raises(ValueError) as refused:
                robot.publish(**args)
            assert robot.sequence == 0, what
            if "up" in change:
                assert str(refused.value).startswith("up"), refused.value
        # Nothing reached the matcher: figures taken after the attempts
        # still count no snapshot...
        done = time.time_ns()
        later = wait_stats(
            stats, "figures taken after the attempts", lambda s: s.taken_ns > done + 300_000_000
        )
        assert later.snapshots_received["robot"] == 0
        # ...and a good snapshot is counted, so the check could fail.
        assert robot.publish(ids, positions, features) == 1
        wait_stats(stats, "the good snapshot counted", lambda s: s.snapshots_accepted["robot"] == 1)
        # Issue 40, case 8: small ids beside 2**64-1 in a list are ids, not
        # "dtype float64"; a sequence past 2**64-1 is refused, not wrapped.
        mixed = [int(i) for i in ids[:-1]] + [2**64 - 1]
        assert robot.publish(mixed, positions, features) == 2
        robot.sequence = 2**64 - 1
        with pytest.raises(ValueError, match="sequence"):
            robot.publish(ids, positions, features)
        assert robot.sequence == 2**64 - 1


def test_no_matcher_and_a_dead_one_give_clear_errors(system: System) -> None:
    with ReferenceClient(**system.ipc) as client:
        with pytest.raises(MatcherNotRunning, match="no vref matcher serves vref/reference"):
            client.by_human_object(1, timeout=0.5)
        with pytest.raises(MatcherNotRunning):
            client.wait_for_matcher(timeout=0.2)

        system.start("matcher", "vref-matcher")
        client.wait_for_matcher(timeout=READY_S)
        assert client.by_human_object(1, timeout=2.0).status == "not_ready"

        # A killed matcher: its server is cleaned up and the error says so.
        system.kill("matcher")
        with pytest.raises(MatcherNotRunning, match="process is gone"):
            client.by_human_object(1, timeout=0.3)
        with pytest.raises(MatcherNotRunning, match="now"):
            client.by_human_object(1, timeout=0.3)

        # A restarted matcher is reached by the same client.
        system.start("matcher", "vref-matcher")
        client.wait_for_matcher(timeout=READY_S)
        assert client.by_human_object(1, timeout=2.0).status == "not_ready"


def test_a_client_over_its_rate_is_told_so_and_the_matcher_keeps_serving(system: System) -> None:
    """Over ``max_queries_per_client_hz`` the matcher lets requests go
    unanswered; that is a refusal, not a stopped matcher."""
    line = "cleanup_interval_ms = 100\n"
    text = system.config.read_text()
    assert line in text
    system.config.write_text(text.replace(line, line + "max_queries_per_client_hz = 20\n"))
    system.start("matcher", "vref-matcher")
    with ReferenceClient(**system.ipc) as client:
        client.wait_for_matcher(timeout=READY_S)
        # A burst is 10 queries at this rate; a tight loop of 200 exceeds it.
        with pytest.raises(QueryRefused, match="max_queries_per_client_hz"):
            for _ in range(200):
                client.by_human_object(1, timeout=2.0)
        assert client.matcher_running
        time.sleep(0.5)  # the bucket refills
        assert client.by_human_object(1, timeout=2.0).status == "not_ready"


def test_a_server_that_does_not_answer_makes_the_query_time_out(system: System) -> None:
    """A matcher that is alive but silent (say, stuck in a long solve): here a
    server of this test that takes requests and never answers."""
    with ReferenceClient(**system.ipc) as client:
        conn = Connection.create(system.settings, "silent-server")
        server = conn.reference().server_builder().create()
        try:
            with pytest.raises(TimeoutError) as timeout:
                client.by_human_object(1, timeout=0.3)
            assert isinstance(timeout.value, AnswerTimeout)
            request = server.receive()
            assert request is not None, "the query reached the server"
            assert request.payload().contents.human_object_id == 1
            request.delete()
        finally:
            server.delete()


def test_queries_check_their_arguments(system: System) -> None:
    with ReferenceClient(**system.ipc) as client:
        bad: list[Callable[[], object]] = [
            lambda: client.by_human_object(-1),
            lambda: client.by_human_object(2**64),
            lambda: client.by_human_object(1.5),  # type: ignore[arg-type]
            lambda: client.by_human_object(True),
            lambda: client.by_ray((0, 0, 0), (0, 0, 0)),
            lambda: client.by_ray((0, 0), (0, 0, 1)),
            lambda: client.by_ray((0, 0, float("nan")), (0, 0, 1)),
            lambda: client.by_ray((0, 0, 0), (0, 0, 1), cone_half_angle=0.0),
            lambda: client.by_ray((0, 0, 0), (0, 0, 1), cone_half_angle=2.0),
            lambda: client.latest_gesture(timeout=0),
            lambda: client.latest_gesture(timeout=float("inf")),
        ]
        for call in bad:
            with pytest.raises(ValueError):
                call()


def test_a_decision_is_read_as_published(system: System) -> None:
    """The matcher of this version does not publish decisions yet: a
    publisher of this test writes one as the Rust DecisionPublisher would
    (same service, same settings), and the reader checks what it claims."""
    with DecisionReader(**system.ipc) as reader:
        assert reader.latest() is None
        conn = Connection.create(system.settings, "decision-writer")
        data, event = conn.decision()
        publisher = conn.slice_publisher(data)
        notifier = event.notifier_builder().create()
        try:

            def publish(pair_count: int, schema: int = wire.SCHEMA_VERSION) -> None:
                sample = publisher.loan_slice_uninit(2)
                header = wire.DecisionHeader.from_address(sample.user_header_ptr)
                ctypes.memset(ctypes.addressof(header), 0, ctypes.sizeof(header))
                header.robot_sequence, header.human_sequence, header.solve_index = 7, 9, 1
                header.rotation[:] = (0, -1, 0, 1, 0, 0, 0, 0, 1)
                header.translation[:] = (0.1, 0.2, 0.3)
                header.flags = wire.DECISION_HEADER_FLAGS["motion"]
                header.method[:5] = tuple(b"rigid")
                header.pair_count = pair_count
                header.schema_version = schema
                entries = (wire.DecisionEntry * 2).from_address(sample.payload_ptr)
                entries[0] = wire.DecisionEntry(
                    1, 993, 0.9, 0, wire.DECISION_ENTRY_FLAGS["partner"]
                )
                entries[1] = wire.DecisionEntry(2, 0, 0.7, wire.ANSWER_STATUSES["no_match"], 0)
                sample.assume_init().send()
                notifier.notify()

            publish(2)
            decision = reader.wait(timeout=5.0)
            assert (decision.robot_sequence, decision.human_sequence) == (7, 9)
            assert decision.method == "rigid"
            assert decision.rotation is not None and decision.translation is not None
            assert decision.rotation.tolist() == [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
            assert [(p.human_track_id, p.robot_track_id, p.status) for p in decision.pairs] == [
                (1, 993, "ok"),
                (2, None, "no_match"),
            ]
            # A header that claims more pairs than the slice carries, or
            # another schema, is refused.
            publish(3)
            with pytest.raises(VrefError, match="counts 3 pairs but carries 2"):
                reader.wait(timeout=5.0)
            publish(2, schema=wire.SCHEMA_VERSION + 1)
            with pytest.raises(VrefError, match="schema version"):
                reader.wait(timeout=5.0)
        finally:
            notifier.delete()
            publisher.delete()
