#!/usr/bin/env bash
# `rigid` on training files as they are and with every feature removed
# (positions only: docs/method.md, "When an answer is ok"): accuracy,
# precision, ECE and the `ok` answers, right and wrong, per file. Reads
# training files only (vref-sim seeds 100-102, lines 1-20 of the external
# sets).
#
#   bash tools/carryover-data.sh && bash tools/without-features.sh [ANSWERS_DIR]
#
# With ANSWERS_DIR, the answers without features are kept there, one
# FILE.jsonl per training file (tools/featureless-recalibration.py reads
# them).
#
# Needs `cargo build --release -p vref -p vref-research --bins --examples` first.
set -euo pipefail
cd "$(dirname "$0")/.."
. tools/need-vref.sh
dir=${VREF_CARRY_DIR:-target/carry}
keep=${1:-}
[ -n "$keep" ] && mkdir -p "$keep"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| training file | features | accuracy | precision | ECE | ok answers (wrong) |"
echo "|---|---|---|---|---|---|"
for f in moi100 moi101 moi102 mrc100 mrc101 mrc102 moi-ext-train mrc-ext-train; do
  python3 tools/strip_features.py "$dir/$f.jsonl" "$work/$f.jsonl"
  for kind in with without; do
    file=$dir/$f.jsonl
    [ "$kind" = without ] && file=$work/$f.jsonl
    "$vref" eval --dataset "$file" --method rigid --answers "$work/a.jsonl" --json |
      python3 -c '
import json, sys
d = json.loads(sys.stdin.read())
ok = [r for r in map(json.loads, open(sys.argv[1])) if r["status"] == "ok"]
print("| %s | %s | %.3f | %.3f | %.3f | %d (%d) |" % (sys.argv[2], sys.argv[3], d["accuracy"],
      d["precision"], d["ece"], len(ok), sum(not r["correct"] for r in ok)))' "$work/a.jsonl" "$f" "$kind"
    if [ -n "$keep" ] && [ "$kind" = without ]; then cp "$work/a.jsonl" "$keep/$f.jsonl"; fi
  done
done
