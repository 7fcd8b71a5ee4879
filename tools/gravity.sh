#!/usr/bin/env bash
# What the views' up vectors do to `rigid` (docs/method.md, "Gravity"), on
# the vref-sim training seeds only (100-109, 30 scenes each): each preset's
# files without up vectors (tools/carryover-data.sh's) and the same scenes
# with them (`vref scenes --up-vectors 1`: 1 degree of tilt error), mean
# accuracy, precision, ECE and solve time; then the `ok` share of the
# unrelated views made from the first seed of each (examples/unrelated,
# seed 11, as tools/carryover-data.sh makes null-train/).
#
#   bash tools/carryover-data.sh && bash tools/gravity.sh ['hypotheses = 50']
#
# An argument sets `[matching.rigid]` settings for the run, as
# tools/rigid-train.sh's does; VREF_METHOD=clipper measures `clipper`
# instead (its rise gate).
# Needs `cargo build --release -p vref -p vref-research --bins --examples` first.
set -euo pipefail
cd "$(dirname "$0")/.."
. tools/need-vref.sh
dir=${VREF_CARRY_DIR:-target/carry}
up=$dir/up
mkdir -p "$up"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
config=$work/vref.toml
python3 tools/rigid-settings.py "${1:-}" "$config"
method=${VREF_METHOD:-rigid}
echo "method: $method; settings: ${1:-defaults}"
for preset in moi mrc; do
  for seed in $(seq 100 109); do
    [ -s "$up/$preset$seed.jsonl" ] ||
      "$vref" scenes --preset "$preset" --count 30 --seed "$seed" --up-vectors 1 \
        --out "$up/$preset$seed.jsonl" 2>/dev/null
  done
done
echo "| files | accuracy | precision (lowest file) | ECE (largest file) | mean solve |"
echo "|---|---|---|---|---|"
for preset in moi mrc; do
  for where in "$dir" "$up"; do
    label="sim $preset, $([ "$where" = "$up" ] && echo "with up vectors" || echo "without")"
    for seed in $(seq 100 109); do
      "$vref" eval --dataset "$where/$preset$seed.jsonl" --method "$method" --json --config "$config"
    done | python3 -c '
import json, sys
r = [json.loads(l) for l in sys.stdin]
mean = lambda k: sum(x[k] for x in r) / len(r)
print("| %s | %.4f | %.4f (%.3f) | %.4f (%.3f) | %.0f us |" % (sys.argv[1],
      mean("accuracy"), mean("precision"), min(x["precision"] for x in r),
      mean("ece"), max(x["ece"] for x in r), mean("mean_solve_us")))' "$label"
  done
done
target/release/examples/unrelated 11 "$work/without" "$dir/moi100.jsonl" "$dir/mrc100.jsonl"
target/release/examples/unrelated 11 "$work/with" "$up/moi100.jsonl" "$up/mrc100.jsonl"
echo
echo "| unrelated views (scene pairs, no clouds) | without up vectors | with |"
echo "|---|---|---|"
for kind in moi100-across moi100-shuffled mrc100-across mrc100-shuffled; do
  cells=""
  for side in without with; do
    "$vref" eval --dataset "$work/$side/$kind.jsonl" --method "$method" --answers "$work/a.jsonl" --json --config "$config" > /dev/null
    cells+=" | $(python3 -c '
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
ok = sum(r["status"] == "ok" for r in rows)
print("%d of %d (%.1f%%)" % (ok, len(rows), 100 * ok / len(rows)))' "$work/a.jsonl")"
  done
  echo "| $kind$cells |"
done
