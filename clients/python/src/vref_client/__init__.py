"""vref_client: talk to vref's matcher from Python over iceoryx2.

Query which robot object a person means (``ReferenceClient``), feed the
matcher snapshots and pointing rays from a Python perception stack or
headset bridge (``SnapshotPublisher``, ``RayPublisher``), and watch it
(``StatsReader`` for ``MatcherStats``, ``DecisionReader`` for ``Decision``).
The wire types live in ``vref_client.wire``; docs/wire.md is the contract.
"""

from .client import DEFAULT_CONE, Alternative, Answer, ReferenceClient
from .errors import (
    AnswerTimeout,
    IpcError,
    MatcherNotRunning,
    QueryRefused,
    VrefError,
    WrongAnswer,
)
from .publishers import RayPublisher, SnapshotPublisher
from .readers import Decision, DecisionPair, DecisionReader, MatcherStats, StatsReader
from .services import IpcSettings
from .wire import SCHEMA_VERSION

__version__ = "0.1.0"

__all__ = [
    "DEFAULT_CONE",
    "SCHEMA_VERSION",
    "Alternative",
    "Answer",
    "AnswerTimeout",
    "Decision",
    "DecisionPair",
    "DecisionReader",
    "IpcError",
    "IpcSettings",
    "MatcherNotRunning",
    "MatcherStats",
    "QueryRefused",
    "RayPublisher",
    "ReferenceClient",
    "SnapshotPublisher",
    "StatsReader",
    "VrefError",
    "WrongAnswer",
]
