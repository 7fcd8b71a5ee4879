#!/usr/bin/env bash
# Regenerates the README's "CMU House with outliers" table: the published
# protocol (Delaunay edges, no appearance term, beta = 2500 pixels^2) but
# with --keep 25 of the 30 landmarks kept at random per frame and view, so
# that about a sixth of the objects have no partner. Mean accuracy,
# precision and ECE per frame gap, every method.
#
#   bash tools/cmu-house-outliers.sh [DATA_DIR] [SEED]   (defaults ../shared/data/cmu_house, 1)
set -euo pipefail
cd "$(dirname "$0")/.."
data=${1:-../shared/data/cmu_house}
seed=${2:-1}
cargo build --release -q -p vref
vref=target/release/vref
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

gaps=(0 10 20 30 40 50 60 70 80 90)
methods=(appearance sm rrwm paper rigid)
declare -A acc prec ece
for gap in "${gaps[@]}"; do
  "$vref" import cmu-house "$data" --gap "$gap" --delaunay --keep 25 --seed "$seed" \
    --out "$work/g$gap.jsonl" 2>/dev/null
  while IFS=$'\t' read -r method a p e; do
    acc[$method,$gap]=$a
    prec[$method,$gap]=$p
    ece[$method,$gap]=$e
  done < <("$vref" eval --dataset "$work/g$gap.jsonl" --beta 2500 --json \
    $(printf -- '--method %s ' "${methods[@]}") |
    python3 -c 'import json,sys
for l in sys.stdin:
    r = json.loads(l)
    print("%s\t%.3f\t%.3f\t%.3f" % (r["method"], r["accuracy"], r["precision"], r["ece"]))')
done

for what in acc prec ece; do
  echo "$what:"
  printf '| method |'; for g in "${gaps[@]}"; do printf ' gap %s |' "$g"; done; echo
  printf '|---|'; for _ in "${gaps[@]}"; do printf -- '---|'; done; echo
  for m in "${methods[@]}"; do
    printf '| %s |' "$m"
    for g in "${gaps[@]}"; do
      case $what in
        acc) printf ' %s |' "${acc[$m,$g]}" ;;
        prec) printf ' %s |' "${prec[$m,$g]}" ;;
        ece) printf ' %s |' "${ece[$m,$g]}" ;;
      esac
    done
    echo
  done
  echo
done
