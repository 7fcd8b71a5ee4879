"""The errors of vref_client. Bad arguments raise ``ValueError`` before
anything touches shared memory."""

from __future__ import annotations


class VrefError(Exception):
    """Base of vref_client's own errors."""


class IpcError(VrefError):
    """An iceoryx2 operation failed; the message says what was being done
    and carries iceoryx2's error."""


class MatcherNotRunning(VrefError, ConnectionError):
    """No matcher serves the reference service under these settings (never
    started, stopped, or its process died)."""


class AnswerTimeout(VrefError, TimeoutError):
    """The matcher did not answer within the timeout (a ``TimeoutError``)."""


class QueryRefused(VrefError):
    """The matcher let the request go unanswered while it kept serving: this
    client asks more often than ``[matcher] max_queries_per_client_hz``."""


class WrongAnswer(VrefError):
    """An answer echoed another request's id."""
