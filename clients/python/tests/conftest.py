"""Real vref processes for the tests: each system runs under its own
iceoryx2 root path and prefix (a temporary directory), so tests never meet
each other or services already running on the machine. Every wait on
another process is bounded; every process is stopped at teardown (SIGTERM,
then SIGKILL)."""

from __future__ import annotations

import gc
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, TypeVar

import pytest

from vref_client import IpcSettings

REPO = Path(__file__).resolve().parents[3]
T = TypeVar("T")

#: How long a service may take to stop after SIGTERM.
STOP_WITHIN_S = 10.0


def bin_dir() -> Path:
    """Where the built services are: $VREF_BIN_DIR, else target/debug (what
    `cargo test --workspace` builds)."""
    return Path(os.environ.get("VREF_BIN_DIR", REPO / "target" / "debug"))


def binary(name: str) -> Path:
    path = bin_dir() / name
    if not path.exists():
        pytest.fail(f"{path} not built: run `cargo build --workspace` (or set VREF_BIN_DIR)")
    return path


# The six-object table of `vref inject --kind valid` (crates/vref-inject/src/scene.rs):
# human object h at HUMAN[h], robot track 1000 - 7h at the rotated position.
HUMAN: dict[int, tuple[float, float, float]] = {
    1: (-0.20, 0.10, 0.80),
    2: (0.00, 0.12, 0.95),
    3: (0.18, 0.08, 0.70),
    4: (0.25, 0.15, 1.05),
    5: (-0.10, 0.14, 1.15),
    6: (0.05, 0.05, 0.60),
}
FEATURE_DIM = 6


def robot_id(h: int) -> int:
    return 1000 - 7 * h


def robot_position(p: tuple[float, float, float]) -> tuple[float, float, float]:
    x, y, z = p
    return (z - 0.9, y + 0.02, -x + 1.0)


def feature(h: int) -> list[float]:
    return [1.0 if k == h - 1 else 0.05 for k in range(FEATURE_DIM)]


def table_dataset() -> str:
    def view(side: str) -> list[dict[str, Any]]:
        return [
            {
                "id": h if side == "human" else robot_id(h),
                "position": list(p if side == "human" else robot_position(p)),
                "feature": feature(h),
            }
            for h, p in HUMAN.items()
        ]

    line = {
        "name": "table",
        "robot": {"objects": view("robot")},
        "human": {"objects": view("human")},
        "ground_truth": [[h, robot_id(h)] for h in HUMAN],
    }
    return json.dumps(line) + "\n"


def eventually(limit_s: float, what: str, check: Callable[[], T | None]) -> T:
    """Calls ``check`` every 50 ms until it returns something, at most
    ``limit_s`` seconds."""
    deadline = time.monotonic() + limit_s
    while True:
        value = check()
        if value is not None:
            return value
        if time.monotonic() > deadline:
            pytest.fail(f"{what}: not within {limit_s} s")
        time.sleep(0.05)


class System:
    """vref processes under one configuration of their own."""

    def __init__(self, directory: Path, tag: str, extra: str = "") -> None:
        self.dir = directory
        root = directory / "iox"
        root.mkdir()
        self.prefix = f"py{os.getpid()}{tag}_"
        self.config = directory / "vref.toml"
        self.config.write_text(
            f'[ipc]\nroot_path = "{root}"\nprefix = "{self.prefix}"\n\n'
            "[matcher]\nstale_after_ms = 2000\ncleanup_interval_ms = 100\n\n"
            f"[matching]\nbeta = 0.01\n{extra}"
        )
        self.settings = IpcSettings.from_toml(self.config)
        self.children: dict[str, subprocess.Popen[bytes]] = {}

    @property
    def ipc(self) -> dict[str, Any]:
        """Keyword arguments of the package's classes for this system."""
        return {
            "namespace": self.settings.namespace,
            "prefix": self.settings.prefix,
            "root_path": self.settings.root_path,
        }

    def start(self, name: str, program: str, *args: str) -> None:
        log = open(self.dir / f"{name}.log", "wb")
        self.children[name] = subprocess.Popen(
            [str(binary(program)), "--config", str(self.config), *args],
            stdin=subprocess.DEVNULL,
            stdout=log,
            stderr=subprocess.STDOUT,
            env={**os.environ, "RUST_LOG": "info"},
            cwd=self.dir,
        )
        log.close()

    def log(self, name: str) -> str:
        path = self.dir / f"{name}.log"
        return path.read_text(errors="replace") if path.exists() else ""

    def signal(self, name: str, sig: signal.Signals) -> None:
        self.children[name].send_signal(sig)

    def kill(self, name: str) -> None:
        child = self.children.pop(name)
        child.kill()
        child.wait(timeout=STOP_WITHIN_S)

    def stop(self) -> dict[str, int | None]:
        """SIGTERM to each, then waits; one that hangs is killed."""
        codes: dict[str, int | None] = {}
        for name, child in self.children.items():
            if child.poll() is None:
                child.terminate()
            try:
                codes[name] = child.wait(timeout=STOP_WITHIN_S)
            except subprocess.TimeoutExpired:
                child.kill()
                child.wait(timeout=STOP_WITHIN_S)
                codes[name] = None
        self.children.clear()
        return codes

    def dataset(self) -> str:
        path = self.dir / "table.jsonl"
        path.write_text(table_dataset())
        return f"dataset:{path}"


@pytest.fixture
def system(request: pytest.FixtureRequest) -> Iterator[System]:
    # A short directory: iceoryx2's event sockets live under the root path,
    # and a Unix socket's path may not exceed 107 bytes.
    directory = Path(tempfile.mkdtemp(prefix="vpy"))
    tag = "".join(c for c in request.node.name if c.isalnum())[-12:]
    s = System(directory, tag)
    try:
        yield s
    finally:
        codes = s.stop()
        report = getattr(request.node, "rep_call", None)
        if report is not None and report.failed:
            # Kept: the services' logs, and iceoryx2 objects a traceback
            # still holds may want their files at exit.
            print(f"logs of the failed test kept in {directory}")
        else:
            gc.collect()
            shutil.rmtree(directory, ignore_errors=True)
        failed = {n: c for n, c in codes.items() if c not in (0, -signal.SIGKILL)}
        if failed:
            logs = "\n".join(f"--- {n}\n{s.log(n)[-2000:]}" for n in failed)
            pytest.fail(f"services did not stop cleanly: {failed}\n{logs}")


@pytest.hookimpl(tryfirst=True, hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Iterator[None]:
    """Records each phase's report on the test, for the fixture's teardown."""
    outcome = yield
    report = outcome.get_result()  # type: ignore[attr-defined]
    setattr(item, f"rep_{report.when}", report)
