#!/usr/bin/env bash
# Sweeps rigid's abstention constants on the training seeds (100-109 of
# both presets, 30 scenes each) and prints, per preset and setting, mean
# accuracy, mean and lowest precision over the ten sets, and mean and
# largest ECE (with the calibration as configured).
#
#   bash tools/abstention-sweep.sh [SHARES] [MOTIONS]
#   e.g. bash tools/abstention-sweep.sh "0.65 0.8 0.9" "0.95 1"
#
# Needs `cargo build --release` first.
set -euo pipefail
cd "$(dirname "$0")/.."
vref=target/release/vref
shares=${1:-"0.65 0.7 0.75 0.8 0.85 0.9"}
motions=${2:-"0.95 0.99 1.0"}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for preset in moi mrc; do
  for seed in $(seq 100 109); do
    "$vref" scenes --preset "$preset" --count 30 --seed "$seed" --out "$work/$preset$seed.jsonl"
  done
done
for share in $shares; do
  for motion in $motions; do
    config="$work/c.toml"
    printf '[matching.rigid]\nabstain_share = %s\nabstain_motion = %s\n' "$share" "$motion" > "$config"
    for preset in moi mrc; do
      for seed in $(seq 100 109); do
        "$vref" eval --dataset "$work/$preset$seed.jsonl" --method rigid --json --config "$config"
      done | python3 -c "
import json, sys
r = [json.loads(l) for l in sys.stdin]
a = [x['accuracy'] for x in r]; p = [x['precision'] for x in r]; e = [x['ece'] for x in r]
print('$preset abstain_share $share abstain_motion $motion: accuracy %.3f, precision mean %.3f lowest %.3f, ECE mean %.3f largest %.3f'
      % (sum(a) / len(a), sum(p) / len(p), min(p), sum(e) / len(e), max(e)))"
    done
  done
done
