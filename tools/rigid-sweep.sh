#!/usr/bin/env bash
# Evaluates `rigid` with some `[matching.rigid]` settings on the training
# seeds (100-109 of both presets, 30 scenes each) and prints, per preset,
# mean accuracy, mean and lowest precision over the ten sets, and mean and
# largest ECE. Unnamed settings keep their defaults.
#
#   bash tools/rigid-sweep.sh 'depth_error = 0.065\nlateral_factor = 0.2'
#
# Needs `cargo build --release` first. Scenes are generated once into
# ${VREF_SWEEP_DIR:-target/rigid-sweep} and reused.
set -euo pipefail
cd "$(dirname "$0")/.."
vref=target/release/vref
settings=${1:-}
dir=${VREF_SWEEP_DIR:-target/rigid-sweep}
mkdir -p "$dir"
for preset in moi mrc; do
  for seed in $(seq 100 109); do
    [ -s "$dir/$preset$seed.jsonl" ] ||
      "$vref" scenes --preset "$preset" --count 30 --seed "$seed" --out "$dir/$preset$seed.jsonl"
  done
done
config=$(mktemp)
trap 'rm -f "$config"' EXIT
printf '[matching.rigid]\n%b\n' "$settings" > "$config"
label=$(printf '%b' "$settings" | tr '\n' ' ')
for preset in moi mrc; do
  for seed in $(seq 100 109); do
    "$vref" eval --dataset "$dir/$preset$seed.jsonl" --method rigid --json --config "$config"
  done | python3 -c "
import json, sys
r = [json.loads(l) for l in sys.stdin]
a = [x['accuracy'] for x in r]; p = [x['precision'] for x in r]; e = [x['ece'] for x in r]
print('%s %s: accuracy %.3f, precision mean %.3f lowest %.3f, ECE mean %.3f largest %.3f'
      % ('$preset', sys.argv[1] or 'defaults', sum(a) / len(a), sum(p) / len(p), min(p), sum(e) / len(e), max(e)))" "$label"
done
