#!/usr/bin/env bash
# Sweeps rigid's abstention constants on every training file (see
# tools/rigid-train.sh for which files and what it prints).
#
#   bash tools/abstention-sweep.sh [SHARES] [MOTIONS]
#   e.g. bash tools/abstention-sweep.sh "0.65 0.8 0.9" "0.95 1"
#
# Needs `cargo build --release -p vref -p vref-research --bins --examples` and
# `bash tools/carryover-data.sh` first.
set -euo pipefail
cd "$(dirname "$0")/.."
shares=${1:-"0.65 0.7 0.75 0.8 0.85 0.9"}
motions=${2:-"0.95 0.99 1.0"}
for share in $shares; do
  for motion in $motions; do
    bash tools/rigid-train.sh "abstain_share = $share\nabstain_motion = $motion"
  done
done
