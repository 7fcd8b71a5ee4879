#!/usr/bin/env bash
# Holds the line on `rigid` across families: regenerates the held-out
# results (tools/method-tables.sh, into a temporary folder) and fails if
# rigid's accuracy, precision or ECE on any held-out set is worse than
# pinned below (today's figures, docs/method.md, less 0.01 of slack for
# accuracy and precision and plus 0.01 for ECE). It also prints each set
# against issue 15's targets (accuracy >= 0.93, precision >= 0.95,
# ECE <= 0.05, accuracy >= best other method + 0.03) and the share of `ok`
# answers on unrelated views (target <= 1%; not all targets are met:
# docs/method.md says which). It fails too if that share is above the
# pinned OK_SHARE (today's 2.6% plus 0.5).
#
#   bash tools/carryover-data.sh && bash tools/rigid-carryover.sh
set -euo pipefail
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
VREF_RESULTS_DIR=$work bash tools/method-tables.sh
python3 - "$work" <<'PY'
import json, os, sys
# set: (accuracy, precision, ECE) pinned
pins = {
    "moi1": (0.967, 0.970, 0.014), "moi2": (0.967, 0.959, 0.020),
    "moi3": (0.984, 0.985, 0.025), "moi4": (0.976, 0.982, 0.025),
    "moi5": (0.985, 0.984, 0.018), "mrc1": (0.956, 0.960, 0.022),
    "mrc2": (0.958, 0.968, 0.038), "mrc3": (0.955, 0.974, 0.051),
    "mrc4": (0.912, 0.955, 0.048), "mrc5": (0.973, 0.979, 0.028),
    "moi-ext-report": (0.915, 0.938, 0.040), "mrc-ext-report": (0.959, 0.958, 0.024),
    "bop-table-report": (0.990, 0.990, 0.015), "bop-floor-report": (0.990, 0.990, 0.013),
}
OK_SHARE = 0.031
work = sys.argv[1]
failed = []
for name in ["method-vrefsim.json", "method-external.json", "method-bop.json"]:
    path = os.path.join(work, name)
    rows = [json.loads(line) for line in open(path)] if os.path.exists(path) else []
    for dataset in dict.fromkeys(r["dataset"] for r in rows):
        these = [r for r in rows if r["dataset"] == dataset]
        rigid = next(r for r in these if r["method"] == "rigid")
        other = max(r["accuracy"] for r in these if r["method"] != "rigid")
        key = os.path.basename(dataset).replace(".jsonl", "")
        a, p, e = rigid["accuracy"], rigid["precision"], rigid["ece"]
        targets = [a >= 0.93, p >= 0.95, e <= 0.05, a >= other + 0.03]
        print(f"{key:18s} accuracy {a:.3f} precision {p:.3f} ECE {e:.3f} "
              f"best other {other:.3f}  targets {'met' if all(targets) else 'MISSED'}")
        pa, pp, pe = pins.get(key, (0.0, 0.0, 1.0))
        if a < pa or p < pp or e > pe:
            failed.append(f"{key}: {a:.3f}/{p:.3f}/{e:.3f} against pinned {pa}/{pp}/{pe}")
rows = [json.loads(line) for line in open(os.path.join(work, "coincidence.json"))]
answers = sum(r["answers"] for r in rows)
ok = sum(r["ok"] for r in rows)
print(f"unrelated views: {ok} of {answers} answers ok ({100 * ok / answers:.1f}%; target <= 1%)")
if ok > OK_SHARE * answers:
    failed.append(f"unrelated views: {100 * ok / answers:.1f}% ok against pinned {100 * OK_SHARE:.1f}%")
if failed:
    print("below the pinned line:\n  " + "\n  ".join(failed))
    sys.exit(1)
PY
