"""The wire types of vref as ctypes structures, schema 3.

Each mirrors a ``#[repr(C)]`` Rust type of ``crates/vref-wire/src/messages.rs``
field for field, with the iceoryx2 type name the Rust side declares
(``#[type_name("vref::...")]``): iceoryx2 refuses to connect ports whose
type names, sizes or alignments differ (``IncompatibleTypes``).
``tests/test_layout.py`` checks every structure against
``docs/wire-layout.json``, which ``vref wire-layout --json`` prints from the
Rust types, so a Rust change not made here fails the tests.
"""

from __future__ import annotations

import ctypes
from typing import Final

import numpy as np

SCHEMA_VERSION: Final = 3
MAX_FEATURE_DIM: Final = 64
FRAME_NAME_LEN: Final = 32
MAX_ALTERNATIVES: Final = 3
MAX_REJECT_REASONS: Final = 32
MAX_ANSWER_STATUSES: Final = 8
MAX_DECISION_PAIRS: Final = 1024

_u8 = ctypes.c_uint8
_u32 = ctypes.c_uint32
_u64 = ctypes.c_uint64
_f32 = ctypes.c_float


class SnapshotHeader(ctypes.Structure):
    """The user header of a snapshot; the objects follow as a slice."""

    _fields_ = [
        ("session", _u64),
        ("sequence", _u64),
        ("timestamp_ns", _u64),
        ("schema_version", _u32),
        ("side", _u32),
        ("object_count", _u32),
        ("feature_dim", _u32),
        ("frame_name", _u8 * FRAME_NAME_LEN),
        ("up", _f32 * 3),
        ("flags", _u32),
    ]

    @staticmethod
    def type_name() -> str:
        return "vref::SnapshotHeader"


class ObjectEntry(ctypes.Structure):
    """One object of a snapshot."""

    _fields_ = [
        ("track_id", _u64),
        ("position", _f32 * 3),
        ("position_sigma", _f32 * 3),
        ("feature", _f32 * MAX_FEATURE_DIM),
    ]

    @staticmethod
    def type_name() -> str:
        return "vref::ObjectEntry"


class PointingRay(ctypes.Structure):
    """A pointing gesture in the human view's frame."""

    _fields_ = [
        ("session", _u64),
        ("sequence", _u64),
        ("timestamp_ns", _u64),
        ("origin", _f32 * 3),
        ("direction", _f32 * 3),
        ("cone_half_angle", _f32),
        ("confidence", _f32),
        ("schema_version", _u32),
        ("reserved", _u32),
    ]

    @staticmethod
    def type_name() -> str:
        return "vref::PointingRay"


class ReferenceQuery(ctypes.Structure):
    """A controller's question to the matcher."""

    _fields_ = [
        ("request_id", _u64),
        ("human_object_id", _u64),
        ("ray_origin", _f32 * 3),
        ("ray_direction", _f32 * 3),
        ("cone_half_angle", _f32),
        ("kind", _u32),
        ("schema_version", _u32),
        ("reserved", _u32),
    ]

    @staticmethod
    def type_name() -> str:
        return "vref::ReferenceQuery"


class Alternative(ctypes.Structure):
    """A next-best candidate of an answer."""

    _fields_ = [
        ("robot_track_id", _u64),
        ("confidence", _f32),
        ("reserved", _u32),
    ]

    @staticmethod
    def type_name() -> str:
        return "vref::Alternative"


class ReferenceAnswer(ctypes.Structure):
    """The matcher's answer."""

    _fields_ = [
        ("request_id", _u64),
        ("human_object_id", _u64),
        ("robot_track_id", _u64),
        ("robot_sequence", _u64),
        ("human_sequence", _u64),
        ("robot_age_us", _u64),
        ("human_age_us", _u64),
        ("solve_age_us", _u64),
        ("ray_age_us", _u64),
        ("position", _f32 * 3),
        ("human_frame_position", _f32 * 3),
        ("confidence", _f32),
        ("status", _u32),
        ("alternative_count", _u32),
        ("schema_version", _u32),
        ("alternatives", Alternative * MAX_ALTERNATIVES),
        ("flags", _u32),
        ("refusal", _u32),
    ]

    @staticmethod
    def type_name() -> str:
        return "vref::ReferenceAnswer"


class MatcherStats(ctypes.Structure):
    """What the matcher has done since it started (published periodically)."""

    _fields_ = [
        ("started_ns", _u64),
        ("taken_ns", _u64),
        ("uptime_ms", _u64),
        ("snapshots_received", _u64 * 2),
        ("snapshots_accepted", _u64 * 2),
        ("rejected", _u64 * MAX_REJECT_REASONS),
        ("answers", _u64 * MAX_ANSWER_STATUSES),
        ("solves", _u64),
        ("rss_kb", _u64),
        ("pid", _u32),
        ("schema_version", _u32),
    ]

    @staticmethod
    def type_name() -> str:
        return "vref::MatcherStats"


class DecisionHeader(ctypes.Structure):
    """The user header of the matcher's decision; entries follow as a slice."""

    _fields_ = [
        ("robot_session", _u64),
        ("robot_sequence", _u64),
        ("robot_timestamp_ns", _u64),
        ("human_session", _u64),
        ("human_sequence", _u64),
        ("human_timestamp_ns", _u64),
        ("solved_ns", _u64),
        ("solve_us", _u64),
        ("solve_index", _u64),
        ("rotation", _f32 * 9),
        ("translation", _f32 * 3),
        ("pair_count", _u32),
        ("flags", _u32),
        ("method", _u8 * 16),
        ("schema_version", _u32),
        ("residual_median", _f32),
    ]

    @staticmethod
    def type_name() -> str:
        return "vref::DecisionHeader"


class DecisionEntry(ctypes.Structure):
    """One human object's outcome in a decision."""

    _fields_ = [
        ("human_track_id", _u64),
        ("robot_track_id", _u64),
        ("confidence", _f32),
        ("status", _u32),
        ("flags", _u32),
        ("residual", _f32),
    ]

    @staticmethod
    def type_name() -> str:
        return "vref::DecisionEntry"


def type_name_of(t: type[ctypes.Structure]) -> str:
    """The iceoryx2 type name a wire structure declares."""
    name: str = t.type_name()  # type: ignore[operator]
    return name


#: Every wire structure, by its Rust name.
WIRE_TYPES: Final[dict[str, type[ctypes.Structure]]] = {
    t.__name__: t
    for t in (
        SnapshotHeader,
        ObjectEntry,
        PointingRay,
        ReferenceQuery,
        Alternative,
        ReferenceAnswer,
        MatcherStats,
        DecisionHeader,
        DecisionEntry,
    )
}

#: ``ObjectEntry`` as a numpy structured dtype: a loaned slice of entries is
#: viewed as an array of it and filled column by column, in place.
OBJECT_ENTRY_DTYPE: Final = np.dtype(
    {
        "names": ["track_id", "position", "position_sigma", "feature"],
        "formats": ["<u8", ("<f4", (3,)), ("<f4", (3,)), ("<f4", (MAX_FEATURE_DIM,))],
        "offsets": [
            ObjectEntry.track_id.offset,
            ObjectEntry.position.offset,
            ObjectEntry.position_sigma.offset,
            ObjectEntry.feature.offset,
        ],
        "itemsize": ctypes.sizeof(ObjectEntry),
    }
)

#: ``DecisionEntry`` as a numpy structured dtype, to read a decision's slice.
DECISION_ENTRY_DTYPE: Final = np.dtype(
    {
        "names": ["human_track_id", "robot_track_id", "confidence", "status", "flags", "residual"],
        "formats": ["<u8", "<u8", "<f4", "<u4", "<u4", "<f4"],
        "offsets": [
            DecisionEntry.human_track_id.offset,
            DecisionEntry.robot_track_id.offset,
            DecisionEntry.confidence.offset,
            DecisionEntry.status.offset,
            DecisionEntry.flags.offset,
            DecisionEntry.residual.offset,
        ],
        "itemsize": ctypes.sizeof(DecisionEntry),
    }
)

# The codes of enum and flag fields (docs/wire-layout.json, record "codes").

#: ``SnapshotHeader.side``; the index of the stats' per-side counters.
SIDE_CODES: Final = {"robot": 0, "human": 1}
#: ``ReferenceQuery.kind``.
QUERY_KINDS: Final = {"human_object": 0, "ray": 1, "latest_gesture": 2}
#: ``ReferenceAnswer.status``, ``DecisionEntry.status``, ``MatcherStats.answers``.
ANSWER_STATUSES: Final = {
    "ok": 0,
    "ambiguous": 1,
    "no_match": 2,
    "not_ready": 3,
    "stale": 4,
    "bad_request": 5,
}
#: ``SnapshotHeader.flags`` bits: ``up`` says ``SnapshotHeader.up`` holds the
#: view's up vector (else it is unknown).
SNAPSHOT_FLAGS: Final = {"up": 1}
#: ``ReferenceAnswer.flags`` bits; ``refusal`` says ``ReferenceAnswer.refusal``
#: holds the reject reason behind a ``stale`` or ``not_ready`` answer.
ANSWER_FLAGS: Final = {
    "solved": 1,
    "human_position": 2,
    "human_position_from_motion": 4,
    "refusal": 8,
}
#: ``DecisionHeader.flags`` bits.
DECISION_HEADER_FLAGS: Final = {"motion": 1, "residuals": 2}
#: ``DecisionEntry.flags`` bits.
DECISION_ENTRY_FLAGS: Final = {"partner": 1, "residual": 2}
#: The matcher's reject reasons: the index of ``MatcherStats.rejected`` and
#: the value of ``ReferenceAnswer.refusal``.
REJECT_REASONS: Final = {
    "schema_version": 0,
    "wrong_side": 1,
    "count_exceeds_slice": 2,
    "feature_dim_too_large": 3,
    "frame_name": 4,
    "uncertainty": 5,
    "empty": 6,
    "too_many_objects": 7,
    "duplicate_id": 8,
    "non_finite_position": 9,
    "absurd_position": 10,
    "non_finite_feature": 11,
    "feature_dim_mismatch": 12,
    "feature_dim_other_side": 13,
    "sequence_backwards": 14,
    "bad_ray": 15,
    "timestamp_future": 16,
    "timestamp_too_old": 17,
    "sequence_jump": 18,
    "query_over_rate": 19,
    "bad_up": 20,
}

#: Every set of codes, by the name docs/wire-layout.json gives it.
CODES: Final[dict[str, dict[str, int]]] = {
    "SideCode": SIDE_CODES,
    "QueryKind": QUERY_KINDS,
    "AnswerStatus": ANSWER_STATUSES,
    "SnapshotHeader.flags": SNAPSHOT_FLAGS,
    "ReferenceAnswer.flags": ANSWER_FLAGS,
    "DecisionHeader.flags": DECISION_HEADER_FLAGS,
    "DecisionEntry.flags": DECISION_ENTRY_FLAGS,
    "RejectReason": REJECT_REASONS,
}

#: Every constant, by its Rust name.
CONSTANTS: Final[dict[str, int]] = {
    "SCHEMA_VERSION": SCHEMA_VERSION,
    "MAX_FEATURE_DIM": MAX_FEATURE_DIM,
    "FRAME_NAME_LEN": FRAME_NAME_LEN,
    "MAX_ALTERNATIVES": MAX_ALTERNATIVES,
    "MAX_REJECT_REASONS": MAX_REJECT_REASONS,
    "MAX_ANSWER_STATUSES": MAX_ANSWER_STATUSES,
    "MAX_DECISION_PAIRS": MAX_DECISION_PAIRS,
}
