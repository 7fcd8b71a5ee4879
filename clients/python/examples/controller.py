"""A robot task's controller: asks the matcher which object the person
points at, and decides what to do with the answer.

    python examples/controller.py        # [ipc] defaults: namespace vref, prefix vref_
    python examples/controller.py --config config/vref.toml --count 10

With the services running (vref-matcher, vref-perception-feed,
vref-gesture-feed), it prints one line per answer: pick the object, ask
the person which one they mean, or wait.
"""

from __future__ import annotations

import argparse
import sys
import time

from vref_client import Answer, MatcherNotRunning, ReferenceClient


def decide(answer: Answer) -> str:
    """What the robot should do with an answer."""
    x, y, z = answer.position
    if answer.status == "ok":
        return (
            f"pick robot object {answer.robot_track_id} at ({x:.3f}, {y:.3f}, {z:.3f}) m "
            f"(confidence {answer.confidence:.2f})"
        )
    if answer.status == "ambiguous":
        options = ", ".join(f"{a.robot_track_id} ({a.confidence:.2f})" for a in answer.alternatives)
        return f"ask the person: object {answer.robot_track_id} or one of {options}?"
    if answer.status == "no_match":
        return "the object pointed at is not in the robot's view"
    if answer.status == "stale":
        age = max(answer.robot_age_us, answer.human_age_us) / 1e3
        return f"wait: a feed is silent (snapshots {age:.0f} ms old)"
    return f"wait: {answer.status}"


def main() -> int:
    parser = argparse.ArgumentParser(description="Ask the matcher what the person points at.")
    parser.add_argument("--config", help="a vref.toml whose [ipc] says where the matcher is")
    parser.add_argument("--period", type=float, default=0.5, help="seconds between queries")
    parser.add_argument("--count", type=int, default=0, help="stop after this many (0: never)")
    parser.add_argument("--human-object", type=int, help="ask about this human object instead")
    args = parser.parse_args()

    client = ReferenceClient.from_config(args.config) if args.config else ReferenceClient()
    with client:
        try:
            client.wait_for_matcher(timeout=10.0)
        except MatcherNotRunning as e:
            print(e, file=sys.stderr)
            return 1
        asked = 0
        while args.count == 0 or asked < args.count:
            if args.human_object is not None:
                answer = client.by_human_object(args.human_object, timeout=1.0)
            else:
                answer = client.latest_gesture(timeout=1.0)
            print(f"human object {answer.human_object_id}: {decide(answer)}", flush=True)
            asked += 1
            time.sleep(args.period)
    return 0


if __name__ == "__main__":
    sys.exit(main())
