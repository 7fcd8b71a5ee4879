#!/usr/bin/env python3
"""What `[matcher] ambiguity_threshold` trades, on training files only: for
each threshold, the share of `rigid`'s answers on unrelated views that
would be `ok` (a partner at that confidence or more), and on each real
training set the share of right answers that would still be `ok` or
`no_match` rather than `ambiguous`. The confidence itself (and so ECE,
accuracy and precision) does not depend on the threshold.

    bash tools/carryover-data.sh    # or tools/reproduce.sh, which makes them
    python3 tools/ok-threshold.py [--carry target/reproduce/carry] [--vref target/release/vref]

Unrelated views: every file of CARRY/null-train (made from training files);
real: vref-sim seeds 100-109 and the training halves of the external and
BOP sets. Runs `vref eval --method rigid --answers` on each (exact tier).
"""

import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile

THRESHOLDS = [0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.91, 0.92, 0.95]
REAL = [f"moi{s}" for s in range(100, 110)] + [f"mrc{s}" for s in range(100, 110)] + [
    "moi-ext-train", "mrc-ext-train", "bop-table-train", "bop-floor-train"]


def answers(vref, dataset, out):
    subprocess.run([vref, "eval", "--dataset", dataset, "--method", "rigid", "--answers", out,
                    "--json"], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return [json.loads(line) for line in open(out)]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--carry", default="target/reproduce/carry")
    p.add_argument("--vref", default="target/release/vref")
    a = p.parse_args()
    nulls = sorted(glob.glob(os.path.join(a.carry, "null-train", "*.jsonl")))
    missing = [n for n in REAL if not os.path.exists(os.path.join(a.carry, n + ".jsonl"))]
    if not nulls or missing:
        sys.exit(f"ok-threshold.py: training files missing in {a.carry} "
                 f"({'no null-train/' if not nulls else ', '.join(missing)}): run tools/carryover-data.sh")
    with tempfile.TemporaryDirectory() as work:
        null = {os.path.basename(f)[:-6]: answers(a.vref, f, os.path.join(work, "n.ans")) for f in nulls}
        real = {n: answers(a.vref, os.path.join(a.carry, n + ".jsonl"), os.path.join(work, "r.ans"))
                for n in REAL}
    families = {"sim moi": [n for n in REAL if n.startswith("moi1")],
                "sim mrc": [n for n in REAL if n.startswith("mrc1")],
                "moi-ext": ["moi-ext-train"], "mrc-ext": ["mrc-ext-train"],
                "bop table": ["bop-table-train"], "bop floor": ["bop-floor-train"]}
    every_null = [r for rows in null.values() for r in rows]
    small = [r for name, rows in null.items() if not name.startswith("clouds") for r in rows]
    head = "| threshold | unrelated `ok`, all | of them, scene pairs (no clouds) | worst file | " + \
        " | ".join(f"{f}: right answers not `ambiguous`" for f in families) + " |"
    print(head)
    print("|" + "---|" * (4 + len(families)))
    for t in THRESHOLDS:
        def ok(rows):
            return sum(1 for r in rows if r["matched"] and r["confidence"] >= t) / max(1, len(rows))
        worst = max(null, key=lambda n: ok(null[n]))
        cells = []
        for names in families.values():
            right = [r for n in names for r in real[n] if r["correct"]]
            cells.append(f"{sum(1 for r in right if r['confidence'] >= t) / max(1, len(right)):.3f}")
        print(f"| {t:g} | {100 * ok(every_null):.2f}% | {100 * ok(small):.1f}% | "
              f"{worst} {100 * ok(null[worst]):.1f}% | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
