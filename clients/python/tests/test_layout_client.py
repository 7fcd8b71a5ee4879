"""tools/layout-client.py, a client made from the wire layout file alone
(issue 40), against the real matcher under this test's own iceoryx2 root
path and prefix."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from typing import Any

from conftest import REPO, System, binary

SCRIPT = REPO / "tools" / "layout-client.py"
#: Hang guards only (a run takes a few seconds): a wedged process fails the
#: test instead of stalling the suite.
HANG_GUARD_S = 300.0

# Runs the script with the vref_client package made unimportable: it must
# need nothing but the layout file and iceoryx2.
RUN_WITHOUT_VREF_CLIENT = (
    "import runpy, sys; sys.modules['vref_client'] = None; "
    "sys.argv = sys.argv[1:]; runpy.run_path(sys.argv[0], run_name='__main__')"
)


def layout_of(system: System) -> list[dict[str, object]]:
    """The layout this system's processes use, as `vref wire-layout --json`
    prints it for its configuration."""
    printed = subprocess.run(
        [str(binary("vref")), "wire-layout", "--json", "--config", str(system.config)],
        capture_output=True,
        text=True,
        check=True,
        timeout=HANG_GUARD_S,
    ).stdout
    return [json.loads(line) for line in printed.splitlines() if line]


def test_the_script_knows_nothing_but_the_layout() -> None:
    source = SCRIPT.read_text()
    assert re.search(r"^\s*(import|from)\s+vref", source, re.MULTILINE) is None
    # No type name, service name or prefix of vref's is written in it.
    for word in ("vref::", "/snapshot", "/reference", "\"vref_", "'vref_", "288", "SCHEMA_VERSION"):
        assert word not in source, word


def run_client(system: System, sent: int, *options: str) -> dict[str, Any]:
    """Starts the matcher and runs the script against it with the layout
    this system's processes use; its summary."""
    records = layout_of(system)
    # It is docs/wire-layout.json but for the prefix, this test's own.
    docs = [
        json.loads(line)
        for line in (REPO / "docs" / "wire-layout.json").read_text().splitlines()
        if line
    ]
    assert records[0]["iceoryx2_prefix"] == system.prefix
    assert [r for r in records if r["record"] != "schema"] == [
        r for r in docs if r["record"] != "schema"
    ]
    assert {**records[0], "iceoryx2_prefix": docs[0]["iceoryx2_prefix"]} == docs[0]
    layout = system.dir / "layout.json"
    layout.write_text("".join(json.dumps(r) + "\n" for r in records))

    system.start("matcher", "vref-matcher")
    assert system.settings.root_path is not None
    run = subprocess.run(
        [
            sys.executable,
            "-c",
            RUN_WITHOUT_VREF_CLIENT,
            str(SCRIPT),
            "--layout",
            str(layout),
            "--root-path",
            system.settings.root_path,
            # Generous: a wait per query that only a wedged matcher reaches.
            "--answer-timeout",
            "10",
            "--ready-timeout",
            "60",
            *options,
        ],
        capture_output=True,
        text=True,
        timeout=HANG_GUARD_S,
    )
    assert run.returncode == 0, f"{run.stderr}\n{system.log('matcher')[-3000:]}"
    summary: dict[str, Any] = json.loads(run.stdout.splitlines()[-1])
    assert summary["sent"] == sent, summary
    return summary


def test_a_client_made_from_the_layout_alone_is_answered(system: System) -> None:
    # Ten rounds of six objects asked three ways.
    summary = run_client(system, 180, "--rounds", "10")
    assert summary["answers"] >= 0.95 * summary["sent"], summary
    assert summary["ok"] >= 0.95 * summary["sent"], summary
    # Every ok answer names the object the client's table says.
    assert summary["correct"] == summary["ok"], summary
    assert summary["wrong"] == [], summary


def test_a_latest_gesture_asked_with_its_ray_uses_that_ray(system: System) -> None:
    """Each object's snapshots and ray sent, then its latest_gesture query,
    and only then their notifications, in that order: the matcher wakes
    on the snapshots' events with the query already waiting. It took rays
    only when the ray's own notification was handled, and answered such
    queries with the previous ray (70 of 119 ok answers named the previous
    object)."""
    # Twenty rounds of six objects, each asked by latest_gesture.
    summary = run_client(
        system, 120, "--rounds", "20", "--kinds", "latest_gesture", "--defer-notify"
    )
    assert summary["answers"] >= 0.95 * summary["sent"], summary
    assert summary["wrong"] == [], summary
    assert summary["correct"] == summary["ok"], summary
    assert summary["ok"] >= 0.95 * summary["sent"], summary
