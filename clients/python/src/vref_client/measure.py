"""How vref states what it measured, as the Rust crate vref-measure does:
one percentile definition (nearest rank) and one duration syntax
(``10s``, ``500ms``). Pure Python, nothing to connect to."""

from __future__ import annotations

import math
import re
from collections.abc import Sequence


def nearest_rank(q: float, n: int) -> int:
    """The 1-based rank of quantile ``q`` (0..1) among ``n`` values:
    ceil(q*n) clamped to 1..n, 0 only for no values. A product within 1e-9
    of a whole number counts as that number (0.07*100 is rank 7)."""
    if n <= 0:
        return 0
    q = 0.0 if math.isnan(q) else min(max(q, 0.0), 1.0)
    x = q * n
    whole = round(x)
    if abs(x - whole) < 1e-9:
        x = whole
    return min(max(math.ceil(x), 1), n)


def percentile(values: Sequence[float], q: float) -> float | None:
    """Nearest rank, as vref_measure::percentile_of (every vref bench);
    the values in any order; ``None`` without values."""
    ordered = sorted(values)
    rank = nearest_rank(q, len(ordered))
    return ordered[rank - 1] if rank else None


_DURATION = re.compile(r"^\s*([0-9]*\.?[0-9]+)\s*(ms|s|min|m|h)?\s*$")
_UNIT_S = {"ms": 0.001, "s": 1.0, "m": 60.0, "min": 60.0, "h": 3600.0}


def parse_duration(text: str, bare_unit: str | None = None) -> float:
    """Seconds of ``10s``, ``500ms``, ``2m``, ``1h`` (decimals allowed), as
    vref_measure::parse_duration; ValueError naming the problem otherwise.
    A bare number is refused unless ``bare_unit`` (``"s"``, ...) gives it a
    unit."""
    match = _DURATION.match(text)
    if match is None:
        raise ValueError(f"`{text}` is not a duration (examples: 10s, 500ms, 2m)")
    number, unit = match.groups()
    given = text.strip()
    unit = unit or bare_unit
    if unit is None:
        raise ValueError(f"`{given}` has no unit: write e.g. {given}s or {given}ms")
    seconds = float(number) * _UNIT_S[unit]
    if not (0.0 < seconds < 8.64e6):
        raise ValueError(f"`{given}` must be a positive duration under 100 days")
    return seconds
