"""The examples work: the Python table feed publishes both views and a
ray, and the example controller picks the object pointed at."""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

from conftest import System, robot_id
from vref_client import ReferenceClient

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_the_controller_picks_what_the_python_feed_points_at(system: System) -> None:
    system.start("matcher", "vref-matcher")
    with ReferenceClient(**system.ipc) as client:
        client.wait_for_matcher(timeout=30.0)
    feed = subprocess.Popen(
        [sys.executable, str(EXAMPLES / "table_feed.py"), "--config", str(system.config)]
        + ["--seconds", "60", "--point-at", "3"],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        # Until the matcher has both views and the ray, the controller
        # prints "wait: ..." lines; then it picks.
        controller = subprocess.run(
            [sys.executable, str(EXAMPLES / "controller.py"), "--config", str(system.config)]
            + ["--count", "30", "--period", "0.1"],
            capture_output=True,
            text=True,
            timeout=60,
        )
    finally:
        feed.send_signal(signal.SIGINT)
        try:
            _, err = feed.communicate(timeout=10)
        except subprocess.TimeoutExpired:
            feed.kill()
            _, err = feed.communicate(timeout=10)
    assert feed.returncode == 0, err.decode()
    assert controller.returncode == 0, controller.stderr
    picks = [line for line in controller.stdout.splitlines() if "pick robot object" in line]
    assert picks, controller.stdout + err.decode()
    assert all(f"pick robot object {robot_id(3)} " in line for line in picks), controller.stdout
