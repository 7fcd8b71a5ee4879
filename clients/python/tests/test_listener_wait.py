"""A listener wait is never shorter than a microsecond: iceoryx2 0.10 takes
a shorter timeout as none and blocks until notified (the Rust test
crates/vref-wire/tests/listener_wait.rs shows it)."""

from __future__ import annotations

import pytest

from vref_client.services import listener_wait


@pytest.mark.parametrize("seconds", [0.0, -1.0, 5e-7, 9.99e-7, 1e-6])
def test_waits_under_a_microsecond_become_one(seconds: float) -> None:
    assert listener_wait(seconds).as_nanos() >= 1000


def test_longer_waits_are_kept() -> None:
    assert listener_wait(0.02).as_micros() == 20000
    assert listener_wait(1.5).as_millis() == 1500
