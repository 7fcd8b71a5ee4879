#!/usr/bin/env bash
# What one known up vector does to `rigid` (docs/method.md, "Gravity"), on
# the vref-sim training seeds only (100-109, 30 scenes each, with 1 degree
# of tilt error as tools/gravity.sh makes them): the same scenes with no up
# vector, the robot's alone, the human's alone, and both; mean accuracy,
# precision and the `ok` answers that are wrong.
#
#   bash tools/carryover-data.sh && bash tools/gravity.sh && bash tools/one-up.sh [SETTINGS]
#
# An argument sets `[matching.rigid]` settings for the run, as
# tools/rigid-train.sh's does (`same_side = false` turns the one-up rule
# off with the plane rule).
# Needs `cargo build --release -p vref -p vref-research --bins --examples` first.
set -euo pipefail
cd "$(dirname "$0")/.."
. tools/need-vref.sh
dir=${VREF_CARRY_DIR:-target/carry}
up=$dir/up
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
config=$work/vref.toml
python3 tools/rigid-settings.py "${1:-}" "$config"
echo "settings: ${1:-defaults}"
echo "| files | up vectors | accuracy | precision | wrong ok answers |"
echo "|---|---|---|---|---|"
for preset in moi mrc; do
  for keep in none robot human both; do
    for seed in $(seq 100 109); do
      f=$up/$preset$seed.jsonl
      [ -s "$f" ] || { echo "one-up.sh: $f missing: run tools/gravity.sh first" >&2; exit 1; }
      python3 - "$f" "$work/$preset$seed-$keep.jsonl" "$keep" <<'PY'
import json, sys
src, out, keep = sys.argv[1:]
with open(out, "w") as g:
    for line in open(src):
        pair = json.loads(line)
        for side in ("robot", "human"):
            if keep not in (side, "both"):
                pair[side].pop("up", None)
        g.write(json.dumps(pair) + "\n")
PY
      "$vref" eval --dataset "$work/$preset$seed-$keep.jsonl" --method rigid --json \
        --config "$config" --answers "$work/answers-$preset$seed-$keep.jsonl"
    done | python3 -c '
import json, sys, glob
r = [json.loads(l) for l in sys.stdin]
mean = lambda k: sum(x[k] for x in r) / len(r)
wrong = 0
for f in glob.glob(sys.argv[3] + "/answers-" + sys.argv[1] + "1??-" + sys.argv[2] + ".jsonl"):
    for line in open(f):
        a = json.loads(line)
        wrong += a["status"] == "ok" and not a["correct"]
print("| sim %s | %s | %.4f | %.4f | %d |" % (sys.argv[1], sys.argv[2], mean("accuracy"), mean("precision"), wrong))' "$preset" "$keep" "$work"
  done
done
