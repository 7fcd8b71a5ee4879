"""The one percentile definition and duration syntax, as in Rust."""

from __future__ import annotations

import pytest

from vref_client.measure import nearest_rank, parse_duration, percentile


def test_p50_of_1_to_1000_is_500() -> None:
    values = [float(v) for v in range(1, 1001)]
    assert percentile(values, 0.5) == 500
    assert percentile(values, 0.99) == 990
    assert percentile(values, 0.999) == 999
    assert percentile(values, 0.0) == 1
    assert percentile(values, 1.0) == 1000


def test_small_sets_unsorted_and_empty() -> None:
    assert percentile([], 0.5) is None
    assert percentile([7.0], 0.99) == 7.0
    assert percentile([5.0, 1.0, 4.0, 2.0, 3.0], 0.5) == 3.0
    assert percentile([1.0, 2.0], 0.5) == 1.0


def test_floating_point_products_do_not_skip_a_rank() -> None:
    assert nearest_rank(0.07, 100) == 7
    assert nearest_rank(0.29, 100) == 29
    assert nearest_rank(0.5, 3) == 2
    assert nearest_rank(0.5, 0) == 0
    assert nearest_rank(2.0, 10) == 10


def test_bench_uses_the_same_definition() -> None:
    from vref_client import bench

    assert bench.percentile is percentile


def test_durations() -> None:
    assert parse_duration("10s") == 10.0
    assert parse_duration("500ms") == 0.5
    assert parse_duration("1.5s") == 1.5
    assert parse_duration("2m") == 120.0
    for bad, says in [
        ("5", "no unit"),
        ("soon", "not a duration"),
        ("0s", "positive"),
        ("-1s", "not a duration"),
    ]:
        with pytest.raises(ValueError, match=says):
            parse_duration(bad)


def test_bench_names_what_is_wrong_with_a_duration() -> None:
    import subprocess
    import sys

    run = subprocess.run(
        [sys.executable, "-m", "vref_client.bench", "--duration", "ten"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert run.returncode == 2
    assert "`ten` is not a duration" in run.stderr


def test_the_bench_takes_bare_seconds() -> None:
    from vref_client import bench

    assert bench.duration_argument("10") == 10.0
    assert bench.duration_argument("0.5") == 0.5
    assert bench.duration_argument("250ms") == 0.25
    assert parse_duration("10", bare_unit="s") == 10.0
    with pytest.raises(ValueError, match="no unit"):
        parse_duration("10")


def test_the_wake_cost_times_both_steps() -> None:
    from vref_client import bench

    wake = bench.wake_cost(0.001, samples=5)
    assert wake["samples"] == 5 and wake["slept_ms"] == 1.0
    assert wake["after_sleep_p50_us"] > 0 and wake["again_p50_us"] > 0
