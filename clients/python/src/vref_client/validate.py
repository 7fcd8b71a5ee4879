"""Argument checks, done before anything touches shared memory: a bad
argument raises ``ValueError`` naming it, and nothing is sent."""

from __future__ import annotations

import math
import operator
from collections.abc import Sequence
from typing import Any

import numpy as np

from . import wire

U64_MAX = 2**64 - 1
#: The matcher takes a ray direction as zero below this length (f64).
MIN_DIRECTION_NORM = 1e-9
#: The matcher refuses an up vector shorter than this (f64, of the float32
#: values sent).
MIN_UP_NORM = 1e-6


def check_u64(name: str, value: Any) -> int:
    """``value`` as a Python int in 0..2**64-1."""
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name}: {value!r} is a bool, not an integer id")
    try:
        number = operator.index(value)
    except TypeError:
        raise ValueError(f"{name}: {value!r} is not an integer") from None
    if not 0 <= number <= U64_MAX:
        raise ValueError(f"{name}: {number} is outside 0..2**64-1")
    return number


def check_timeout(timeout: Any) -> float:
    """A finite positive number of seconds."""
    try:
        seconds = float(timeout)
    except (TypeError, ValueError):
        raise ValueError(f"timeout: {timeout!r} is not a number of seconds") from None
    if not (math.isfinite(seconds) and seconds > 0):
        raise ValueError(f"timeout: {timeout!r} must be a finite number of seconds > 0")
    return seconds


def f32_array(name: str, value: Any, shape: tuple[int, ...]) -> np.ndarray:
    """``value`` as a float32 array of ``shape`` with only finite entries
    (checked after the conversion: a float64 beyond float32's range is
    refused rather than sent as infinity)."""
    if isinstance(value, np.ndarray) and value.dtype.kind not in "fiu":
        raise ValueError(f"{name}: dtype {value.dtype} is not numeric")
    if not isinstance(value, np.ndarray):
        # numpy would read "1.5" and True as numbers: a list of strings or
        # booleans is a caller's mistake, not a position or a feature.
        try:
            kind = np.asarray(value).dtype.kind
        except (TypeError, ValueError) as e:
            raise ValueError(f"{name}: not an array of numbers ({e})") from None
        if kind not in "fiu":
            what = {"b": "booleans", "U": "strings", "S": "bytes"}.get(kind, "not numbers")
            raise ValueError(f"{name}: {what}, expected numbers")
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: not an array of numbers ({e})") from None
    if array.shape != shape:
        raise ValueError(f"{name}: shape {array.shape}, expected {shape}")
    bad = ~np.isfinite(array)
    if bad.any():
        where = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ValueError(f"{name}{list(where)} is {array[where]}, not a finite number")
    # Overflow is found and refused below, not warned about.
    with np.errstate(over="ignore"):
        single = array.astype(np.float32)
    overflow = ~np.isfinite(single)
    if overflow.any():
        where = tuple(int(i) for i in np.argwhere(overflow)[0])
        raise ValueError(f"{name}{list(where)} is {array[where]}, beyond float32's range")
    return single


def vector3(name: str, value: Any) -> tuple[float, float, float]:
    v = f32_array(name, value, (3,))
    return (float(v[0]), float(v[1]), float(v[2]))


def ray_parts(
    origin: Sequence[float] | np.ndarray,
    direction: Sequence[float] | np.ndarray,
    cone_half_angle: Any,
) -> tuple[tuple[float, float, float], tuple[float, float, float], float]:
    """A ray's origin, direction and cone half-angle as the matcher will
    accept them: finite, a direction longer than 1e-9, a cone in (0, pi/2]
    (compared as float32, as sent)."""
    o = vector3("origin", origin)
    d = vector3("direction", direction)
    if math.sqrt(sum(c * c for c in d)) <= MIN_DIRECTION_NORM:
        raise ValueError(f"direction {list(d)}: must not be zero")
    cone = check_angle(cone_half_angle)
    return o, d, cone


def up_vector(up: Any) -> tuple[float, float, float] | None:
    """A view's up vector as the matcher will accept it: ``None``
    (unknown), or three finite numbers (after the conversion to float32)
    at least 1e-6 long, in any units."""
    if up is None:
        return None
    v = vector3("up", up)
    if math.hypot(*v) < MIN_UP_NORM:
        raise ValueError(f"up {list(v)}: must not be zero (length at least {MIN_UP_NORM})")
    return v


def check_angle(cone_half_angle: Any) -> float:
    try:
        cone = float(np.float32(cone_half_angle))
    except (TypeError, ValueError):
        raise ValueError(f"cone_half_angle: {cone_half_angle!r} is not a number") from None
    if not (cone > 0 and cone <= math.pi / 2):
        raise ValueError(
            f"cone_half_angle: {cone_half_angle!r} (as float32 {cone!r})"
            " must be in (0, pi/2] radians"
        )
    return cone


def check_confidence(confidence: Any) -> float:
    try:
        value = float(np.float32(confidence))
    except (TypeError, ValueError):
        raise ValueError(f"confidence: {confidence!r} is not a number") from None
    if not 0.0 <= value <= 1.0:
        raise ValueError(f"confidence: {confidence!r} must be in [0, 1]")
    return value


def frame_bytes(frame: Any) -> bytes:
    """A frame name as the wire carries it: UTF-8, at most 32 bytes, no NUL."""
    if not isinstance(frame, str):
        raise ValueError(f"frame: {frame!r} is not a string")
    try:
        data = frame.encode("utf-8")
    except UnicodeEncodeError as e:
        raise ValueError(f"frame: {frame!r} is not valid text ({e.reason})") from None
    if len(data) > wire.FRAME_NAME_LEN:
        raise ValueError(
            f"frame: {frame!r} is {len(data)} bytes of UTF-8, at most {wire.FRAME_NAME_LEN}"
        )
    if b"\0" in data:
        raise ValueError(f"frame: {frame!r} contains a NUL character")
    return data


def check_timestamp(timestamp_ns: Any) -> int:
    return check_u64("timestamp_ns", timestamp_ns)


def track_ids(value: Any) -> np.ndarray:
    """Track ids as uint64, one dimension, unique, none negative."""
    if isinstance(value, np.ndarray):
        array = value
    elif isinstance(value, Sequence) and any(
        isinstance(v, int) and not isinstance(v, bool) and v > np.iinfo(np.int64).max
        for v in value
    ):
        # numpy makes float64 of small ids beside one beyond int64 (which
        # would lose digits): each is checked as the integer it is.
        array = np.array([check_u64("track_ids", v) for v in value], np.uint64)
    else:
        try:
            array = np.asarray(value)
        except (TypeError, ValueError, OverflowError) as e:
            raise ValueError(f"track_ids: not an array of integers ({e})") from None
        if array.size == 0:
            array = array.astype(np.uint64)
        elif array.dtype == object:
            # Python ints beyond int64 (up to 2**64-1) land here.
            try:
                array = np.array([check_u64("track_ids", v) for v in array.ravel()], np.uint64)
            except ValueError as e:
                raise ValueError(str(e)) from None
    if array.ndim != 1:
        raise ValueError(f"track_ids: shape {array.shape}, expected one dimension (n,)")
    if array.dtype.kind == "b" or array.dtype.kind not in "iu":
        raise ValueError(f"track_ids: dtype {array.dtype} is not an integer type")
    if array.dtype.kind == "i" and array.size and int(array.min()) < 0:
        index = int(np.argmin(array))
        raise ValueError(f"track_ids[{index}] is {int(array[index])}, ids are 0..2**64-1")
    ids = array.astype(np.uint64)
    unique, counts = np.unique(ids, return_counts=True)
    if unique.size != ids.size:
        duplicate = int(unique[np.argmax(counts > 1)])
        raise ValueError(f"track_ids: id {duplicate} appears more than once")
    return ids


def objects(
    track_ids_: Any,
    positions: Any,
    features: Any,
    position_sigma: Any,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The arrays of a snapshot, checked and converted: ids (n,) uint64,
    positions (n, 3), features (n, d) with d <= 64 (``None``: d = 0), sigma
    (n, 3) >= 0 (``None``: zeros; a scalar or (3,) is broadcast), float32."""
    ids = track_ids(track_ids_)
    n = int(ids.size)
    pos = f32_array("positions", positions, (n, 3))
    if features is None:
        feat = np.zeros((n, 0), np.float32)
    else:
        shape = np.shape(features)
        if len(shape) != 2 or shape[0] != n:
            raise ValueError(f"features: shape {shape}, expected ({n}, d) with d <= 64")
        if shape[1] > wire.MAX_FEATURE_DIM:
            raise ValueError(
                f"features: {shape[1]} entries per object, at most {wire.MAX_FEATURE_DIM}"
            )
        feat = f32_array("features", features, (n, int(shape[1])))
    if position_sigma is None:
        sigma = np.zeros((n, 3), np.float32)
    else:
        try:
            full = np.broadcast_to(np.asarray(position_sigma, dtype=np.float64), (n, 3))
        except ValueError:
            raise ValueError(
                f"position_sigma: shape {np.shape(position_sigma)} does not broadcast to ({n}, 3)"
            ) from None
        sigma = f32_array("position_sigma", full, (n, 3))
        if (sigma < 0).any():
            where = tuple(int(i) for i in np.argwhere(sigma < 0)[0])
            raise ValueError(f"position_sigma{list(where)} is {sigma[where]}, must be >= 0")
    return ids, pos, feat, sigma
