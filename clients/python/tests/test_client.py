"""The client's fast decoding of answers agrees with the ctypes structure
(which test_layout.py checks against the Rust layout)."""

from __future__ import annotations

import ctypes

from vref_client import Alternative, Answer, wire
from vref_client.client import ANSWER_STRUCT


def test_the_answer_struct_covers_the_wire_type() -> None:
    assert ANSWER_STRUCT.size == ctypes.sizeof(wire.ReferenceAnswer)


def test_every_field_is_decoded_from_its_own_bytes() -> None:
    a = wire.ReferenceAnswer()
    # Distinct values everywhere, so that a field read from another's
    # bytes shows.
    for k, name in enumerate(
        [
            "request_id",
            "human_object_id",
            "robot_track_id",
            "robot_sequence",
            "human_sequence",
            "robot_age_us",
            "human_age_us",
            "solve_age_us",
            "ray_age_us",
        ]
    ):
        setattr(a, name, 2**40 + 1000 * k)
    a.position[:] = (0.5, -1.25, 2.0)
    a.human_frame_position[:] = (3.5, 4.5, -5.5)
    a.confidence = 0.75
    a.status = wire.ANSWER_STATUSES["ambiguous"]
    a.alternative_count = 2
    a.schema_version = wire.SCHEMA_VERSION
    a.alternatives[0] = wire.Alternative(11, 0.25, 0)
    a.alternatives[1] = wire.Alternative(12, 0.125, 0)
    a.alternatives[2] = wire.Alternative(13, 0.0625, 0)
    a.flags = wire.ANSWER_FLAGS["solved"] | wire.ANSWER_FLAGS["human_position"]
    answer = Answer.from_wire(a)
    assert answer == Answer(
        status="ambiguous",
        request_id=2**40,
        human_object_id=2**40 + 1000,
        robot_track_id=2**40 + 2000,
        position=(0.5, -1.25, 2.0),
        confidence=0.75,
        alternatives=(Alternative(11, 0.25), Alternative(12, 0.125)),
        robot_sequence=2**40 + 3000,
        human_sequence=2**40 + 4000,
        robot_age_us=2**40 + 5000,
        human_age_us=2**40 + 6000,
        solved=True,
        solve_age_us=2**40 + 7000,
        ray_age_us=2**40 + 8000,
        human_frame_position=(3.5, 4.5, -5.5),
        human_frame_position_from_motion=False,
        flags=3,
    )
    assert not answer.ok


def test_a_stale_answer_names_the_refusal_behind_it() -> None:
    a = wire.ReferenceAnswer()
    a.status = wire.ANSWER_STATUSES["stale"]
    a.refusal = wire.REJECT_REASONS["feature_dim_other_side"]
    assert Answer.from_wire(a).refusal is None, "without the flag it says nothing"
    a.flags = wire.ANSWER_FLAGS["refusal"]
    assert Answer.from_wire(a).refusal == "feature_dim_other_side"


def test_unknown_status_reads_as_bad_request_and_counts_are_bounded() -> None:
    a = wire.ReferenceAnswer()
    a.status = 99
    a.alternative_count = 7
    answer = Answer.from_wire(a)
    assert answer.status == "bad_request"
    assert len(answer.alternatives) == wire.MAX_ALTERNATIVES
    assert answer.human_frame_position is None


def test_the_query_struct_packs_as_the_wire_type() -> None:
    from vref_client.client import _PACK_QUERY, QUERY_REST

    q = wire.ReferenceQuery()
    assert 16 + QUERY_REST.size == ctypes.sizeof(q)
    _PACK_QUERY(q, 0, 11, 12, QUERY_REST.pack(1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 0.25, 3, 7, 8))
    assert (q.request_id, q.human_object_id) == (11, 12)
    assert list(q.ray_origin) == [1.0, 2.0, 3.0] and list(q.ray_direction) == [4.0, 5.0, 6.0]
    assert (q.cone_half_angle, q.kind, q.schema_version, q.reserved) == (0.25, 3, 7, 8)


def test_the_queries_without_a_ray_pack_as_their_ctypes_struct() -> None:
    from vref_client import client

    for kind, rest in [
        ("human_object", client._HUMAN_OBJECT_REST),
        ("latest_gesture", client._LATEST_GESTURE_REST),
    ]:
        q = wire.ReferenceQuery(
            request_id=5,
            human_object_id=9,
            kind=wire.QUERY_KINDS[kind],
            schema_version=wire.SCHEMA_VERSION,
        )
        packed = wire.ReferenceQuery()
        client._PACK_QUERY(packed, 0, 5, 9, rest)
        assert bytes(packed) == bytes(q), kind
