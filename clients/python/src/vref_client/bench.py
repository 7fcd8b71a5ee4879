"""``python -m vref_client.bench``: the Python client's round trip beside
the Rust client's, against one matcher, in one run.

Starts the matcher and both synthetic feeds (built binaries) under an
iceoryx2 root path and prefix of its own, then for ``--duration`` sends
latest-gesture queries at ``--rate`` from this process (``ReferenceClient``)
while ``vref bench client`` does the same from a Rust ``ReferenceClient``
in its own process, so that both meet the same load. Prints round-trip
percentiles of answers from the cached solution (and after a solve) for
both, their ratio, and the CPU time this process spent: over the run, inside
the queries, and during one second spent waiting for an answer that never
comes (a server of its own that never answers); then, with the services
stopped, what one small Python step costs right after sleeping one query
period against the same step again at once (``wake_cost``). Percentiles
are printed, never judged.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import select
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from . import wire
from .client import ReferenceClient
from .errors import AnswerTimeout
# Re-exported: the one definition, as vref_client.bench.percentile was before.
from .measure import parse_duration as parse_duration
from .measure import percentile as percentile
from .services import Connection, IpcSettings

SERVICES = ("vref-matcher", "vref-perception-feed", "vref-gesture-feed")
READY_S = 30.0
QUERY_TIMEOUT_S = 2.0


def duration_argument(text: str) -> float:
    """``parse_duration`` for argparse, which would otherwise print only
    "invalid value" and drop the reason. A bare number is seconds here
    (``--duration 10``, the spelling issue 16 gives), unlike vref's own
    flags: this bench has no other unit a plain number could mean."""
    try:
        return parse_duration(text, bare_unit="s")
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from e


def rounded(value: float | None, digits: int = 1) -> float | None:
    return None if value is None else round(value, digits)


def find_binaries(explicit: str | None) -> Path:
    """Where the services are: --bin-dir, $VREF_BIN_DIR, target/release or
    target/debug under the working directory, or the directory of `vref` on
    PATH."""
    candidates = [explicit, os.environ.get("VREF_BIN_DIR"), "target/release", "target/debug"]
    on_path = shutil.which("vref")
    if on_path:
        candidates.append(str(Path(on_path).parent))
    for c in candidates:
        if c and all((Path(c) / s).exists() for s in (*SERVICES, "vref")):
            return Path(c).resolve()
    raise SystemExit(
        "vref_client.bench: the vref binaries (vref, vref-matcher, vref-perception-feed, "
        "vref-gesture-feed) were not found: run `cargo build --release` in the repository "
        "and start this from its root, or pass --bin-dir"
    )


class Services:
    """The matcher and both feeds, run by ``vref up`` (the one launcher)
    under an iceoryx2 root path and prefix of their own, which it names in
    its first line: ``config PATH``."""

    def __init__(self, bins: Path, directory: Path, objects: int) -> None:
        self.dir = directory
        self.log = directory / "vref-up.log"
        with open(self.log, "wb") as log:
            self.up = subprocess.Popen(
                [str(bins / "vref"), "up", "--objects", str(objects)],
                # Unbuffered: a line read leaves the next in the pipe, where
                # select sees it.
                bufsize=0,
                stdin=subprocess.DEVNULL,
                stdout=subprocess.PIPE,
                stderr=log,
            )
        first = self._line()
        if not first.startswith("config "):
            self.stop()
            raise SystemExit(f"vref_client.bench: vref up said {first!r}: {self._last_log()}")
        self.config = Path(first.removeprefix("config "))
        settings = IpcSettings.from_toml(self.config)
        self.prefix: str = settings.prefix
        self.root: str = settings.root_path or ""
        # vref up says so once the matcher answers the latest gesture.
        said = self._line()
        if said != "ready":
            self.stop()
            raise SystemExit(f"vref_client.bench: vref up said {said!r}: {self._last_log()}")

    def _line(self) -> str:
        """The next line of ``vref up``, or "" once it ended; bounded, as
        ``vref up`` itself gives up on services not ready in time."""
        assert self.up.stdout is not None
        ready, _, _ = select.select([self.up.stdout], [], [], READY_S + 10)
        return self.up.stdout.readline().decode().strip() if ready else ""

    def _last_log(self) -> str:
        text = self.log.read_text(errors="replace").strip()
        return text.splitlines()[-1] if text else "(no log)"

    def check(self) -> None:
        if self.up.poll() is not None:
            raise SystemExit(
                f"vref_client.bench: vref up exited ({self.up.returncode}): {self._last_log()}"
            )

    def stop(self) -> None:
        if self.up.poll() is None:
            self.up.terminate()
        try:
            self.up.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.up.kill()
            self.up.wait(timeout=10)
        if self.up.stdout is not None:
            self.up.stdout.close()


def measure_python(client: ReferenceClient, rate: float, duration: float) -> dict[str, Any]:
    cached: list[float] = []
    solved: list[float] = []
    other = timeouts = 0
    # The (robot, human) sequences of the last answer's solution: the first
    # answer from a new solution counts apart, as `vref bench query` does.
    last_solution: tuple[int, int] | None = None
    inside_cpu = inside_wall = 0.0
    period = 1.0 / rate
    cpu0, wall0 = time.process_time(), time.perf_counter()
    end = wall0 + duration
    while time.perf_counter() < end:
        # The CPU clock is a system call: read outside the timed span.
        c0 = time.process_time()
        started = time.perf_counter()
        try:
            answer = client.latest_gesture(timeout=QUERY_TIMEOUT_S)
        except AnswerTimeout:
            timeouts += 1
            continue
        took = time.perf_counter() - started
        inside_cpu += time.process_time() - c0
        inside_wall += took
        if answer.status in ("ok", "ambiguous"):
            solution = (answer.robot_sequence, answer.human_sequence)
            new = last_solution is not None and last_solution != solution
            last_solution = solution
            (solved if new else cached).append(took * 1e6)
        else:
            other += 1
        rest = period - (time.perf_counter() - started)
        if rest > 0:
            time.sleep(rest)
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    return {
        "client": "python",
        "query": "latest_gesture",
        "cached_p50_us": rounded(percentile(cached, 0.5)),
        "cached_p99_us": rounded(percentile(cached, 0.99)),
        "solve_p50_us": rounded(percentile(solved, 0.5)),
        "solve_p99_us": rounded(percentile(solved, 0.99)),
        "cached_count": len(cached),
        "solve_count": len(solved),
        "other_count": other,
        "timeouts": timeouts,
        # CPU time of this process over the whole run and inside the
        # queries, as a share of the wall time: a client that spun while
        # waiting would show a share near 1 inside the queries.
        "cpu_share_run": round(cpu / wall, 4),
        "cpu_share_in_queries": round(inside_cpu / inside_wall, 4) if inside_wall else None,
    }


def cpu_waiting(services: Services, seconds: float) -> dict[str, Any]:
    """CPU time spent by this process while a query waits ``seconds`` for an
    answer that never comes: a server of its own, under a namespace of its
    own, takes the request and never answers."""
    namespace = "vref/bench-silent"
    settings = IpcSettings(namespace=namespace, prefix=services.prefix, root_path=services.root)
    conn = Connection.create(settings, "vref-py-bench-silent")
    server = conn.reference().server_builder().create()
    try:
        with ReferenceClient(namespace, services.prefix, services.root) as client:
            before = resource.getrusage(resource.RUSAGE_SELF)
            w0 = time.perf_counter()
            try:
                client.latest_gesture(timeout=seconds)
                outcome = "answered"
            except AnswerTimeout:
                outcome = "timed out"
            wall = time.perf_counter() - w0
            after = resource.getrusage(resource.RUSAGE_SELF)
    finally:
        server.delete()
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {
        "wait_s": round(wall, 3),
        "wait_outcome": outcome,
        "wait_cpu_ms": round(cpu * 1e3, 2),
        "wait_cpu_share": round(cpu / wall, 4),
        "wait_voluntary_switches": after.ru_nvcsw - before.ru_nvcsw,
    }


def wake_cost(period: float, samples: int = 300) -> dict[str, Any]:
    """What one small Python step (two ctypes field stores, as a query makes)
    costs right after this process slept one query period, against the same
    step again at once; measured after the services stopped, so no vref
    process runs meanwhile. On a virtual machine the first steps after a
    sleep run from cold caches, and a query is many such steps."""

    def step(q: Any) -> None:
        q.request_id = 1
        q.kind = 3

    q = wire.ReferenceQuery()
    after_sleep: list[float] = []
    again: list[float] = []
    clock = time.perf_counter_ns
    for _ in range(samples):
        time.sleep(period)
        t0 = clock()
        step(q)
        t1 = clock()
        step(q)
        t2 = clock()
        after_sleep.append((t1 - t0) / 1e3)
        again.append((t2 - t1) / 1e3)
    return {
        "slept_ms": round(period * 1e3, 3),
        "samples": samples,
        "after_sleep_p50_us": rounded(percentile(after_sleep, 0.5), 2),
        "again_p50_us": rounded(percentile(again, 0.5), 2),
    }


def run(args: argparse.Namespace) -> dict[str, Any]:
    bins = find_binaries(args.bin_dir)
    directory = Path(tempfile.mkdtemp(prefix="vpb"))
    services = Services(bins, directory, args.objects)
    failed = True
    try:
        client = ReferenceClient("vref", services.prefix, services.root, node="vref-py-bench")
        try:
            rust = subprocess.Popen(
                [
                    str(bins / "vref"),
                    "bench",
                    "client",
                    "--config",
                    str(services.config),
                    "--rate",
                    str(args.rate),
                    "--duration",
                    f"{round(args.duration * 1000)}ms",
                    "--json",
                ],
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                stdin=subprocess.DEVNULL,
            )
            python = measure_python(client, args.rate, args.duration)
            try:
                out, err = rust.communicate(timeout=args.duration + READY_S + 30)
            except subprocess.TimeoutExpired:
                rust.kill()
                rust.communicate(timeout=10)
                raise SystemExit("vref_client.bench: vref bench client did not finish") from None
            if rust.returncode != 0:
                raise SystemExit(f"vref_client.bench: vref bench client failed: {err.decode()}")
            rust_report = json.loads(out.decode().strip().splitlines()[-1])
            services.check()
        finally:
            client.close()
        failed = False
        waiting = cpu_waiting(services, 1.0)
    finally:
        services.stop()
        if not failed:
            wake = wake_cost(1.0 / args.rate)
        if failed:
            print(f"vref_client.bench: the services' logs are in {directory}", file=sys.stderr)
        else:
            shutil.rmtree(directory, ignore_errors=True)
    py50, rust50 = python["cached_p50_us"], rust_report["cached_p50_us"]
    return {
        "objects": args.objects,
        "rate_hz": args.rate,
        "duration_s": args.duration,
        "binaries": str(bins),
        "python_cached_p50_us": py50,
        "rust_cached_p50_us": rust50,
        "ratio_cached_p50": round(py50 / rust50, 3) if py50 and rust50 else None,
        "python_cached_p99_us": python["cached_p99_us"],
        "rust_cached_p99_us": rust_report["cached_p99_us"],
        "python": python,
        "rust": rust_report,
        "waiting": waiting,
        "wake": wake,
    }


def table(r: dict[str, Any]) -> str:
    py, rust, wait = r["python"], r["rust"], r["waiting"]
    lines = [
        f"{r['objects']} objects, latest-gesture queries at {r['rate_hz']:g}/s per client "
        f"for {r['duration_s']:g} s, binaries in {r['binaries']}",
        f"{'round trip':<28}{'count':>8}{'p50 us':>10}{'p99 us':>10}",
    ]
    for name, rep in (("python", py), ("rust", rust)):
        for kind in ("cached", "solve"):
            p50, p99 = rep[f"{kind}_p50_us"], rep[f"{kind}_p99_us"]
            lines.append(
                f"{name + ' ' + ('cached answer' if kind == 'cached' else 'after a solve'):<28}"
                f"{rep[f'{kind}_count']:>8}{p50 if p50 is not None else '-':>10}"
                f"{p99 if p99 is not None else '-':>10}"
            )
    lines.append(f"python / rust, cached p50: {r['ratio_cached_p50']}")
    lines.append(
        f"python CPU: {py['cpu_share_run']:.1%} of the run, "
        f"{py['cpu_share_in_queries']:.1%} inside queries; waiting {wait['wait_s']} s for an "
        f"answer that never came ({wait['wait_outcome']}) cost {wait['wait_cpu_ms']} ms CPU "
        f"({wait['wait_cpu_share']:.2%})"
    )
    wake = r["wake"]
    lines.append(
        f"one Python step (two ctypes field stores) right after sleeping {wake['slept_ms']:g} ms: "
        f"p50 {wake['after_sleep_p50_us']} us; the same step again at once: "
        f"{wake['again_p50_us']} us (services stopped)"
    )
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m vref_client.bench",
        description=__doc__.split("\n\n")[1] if __doc__ else None,
    )
    parser.add_argument(
        "--duration", type=duration_argument, default=10.0, help="how long to measure: 10s, 500ms, or seconds (10)"
    )
    parser.add_argument(
        "--rate", type=float, default=200.0, help="queries per second of each client"
    )
    parser.add_argument("--objects", type=int, default=32, help="objects in the synthetic world")
    parser.add_argument("--bin-dir", help="where the vref binaries are (default: see --help)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args(argv)
    if not (args.duration > 0 and 0 < args.rate <= 1000 and args.objects >= 2):
        parser.error("--duration > 0, --rate in (0, 1000] and --objects >= 2")
    report = run(args)
    sys.stdout.write(json.dumps(report) + "\n" if args.json else table(report))
    return 0


if __name__ == "__main__":
    sys.exit(main())
