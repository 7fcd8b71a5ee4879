#!/usr/bin/env bash
# How far the measures `rigid` has of a motion against chance can tell two
# views of one scene from views that share nothing (docs/method.md, "Views
# with nothing in common"), on the training files only: every scene's
# significance, margin, fit, share and size, from `vref eval --answers`,
# real training files (sim seeds 100-109, the external and BOP training
# halves) against the unrelated training views (null-train/, scene pairs,
# no clouds). A logistic model of "shares a scene" on those measures,
# fitted with both kinds weighing the same, gives each scene the odds its
# measures carry; with a prior probability that the views share a scene,
# every partner's confidence is multiplied by the posterior. Printed per
# prior: the unrelated answers still `ok` (confidence >= 0.5) and the
# largest ECE of a real training file: what the measures allow at best.
#
#   bash tools/carryover-data.sh && bash tools/shared-scene.sh
#
# Needs `cargo build --release -p vref -p vref-research --bins --examples` first, and numpy
# (the test venv has it: PYTHON=target/python-venv/bin/python).
set -euo pipefail
cd "$(dirname "$0")/.."
. tools/need-vref.sh
dir=${VREF_CARRY_DIR:-target/carry}
python=${PYTHON:-target/python-venv/bin/python}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for f in "$dir"/moi10?.jsonl "$dir"/mrc10?.jsonl "$dir"/*-train.jsonl; do
  "$vref" eval --dataset "$f" --method rigid --answers "$work/real-$(basename "$f")" --json >/dev/null
done
for f in "$dir"/null-train/*.jsonl; do
  case "$f" in *clouds*) continue ;; esac
  "$vref" eval --dataset "$f" --method rigid --answers "$work/null-$(basename "$f")" --json >/dev/null
done
"$python" tools/shared-scene.py "$work"
