#!/usr/bin/env bash
# Regenerates the README's CMU House table: the published protocol (30 vs 30
# landmarks, Delaunay edges, no appearance term, beta = 2500 pixels^2),
# mean accuracy per frame gap, next to the published figures.
#
#   bash tools/cmu-house-table.sh [DATA_DIR]     (default ../shared/data/cmu_house)
set -euo pipefail
cd "$(dirname "$0")/.."
data=${1:-../shared/data/cmu_house}
cargo build --release -q -p vref
vref=target/release/vref
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

declare -A published=(
  [sm,0]=1.0 [sm,50]=.914 [sm,90]=.637
  [rrwm,0]=1.0 [rrwm,50]=1.0 [rrwm,90]=.997
)
gaps=(0 10 20 30 40 50 60 70 80 90)
methods=(appearance sm rrwm paper)

declare -A acc solve
for gap in "${gaps[@]}"; do
  "$vref" import cmu-house "$data" --gap "$gap" --delaunay --out "$work/g$gap.jsonl"
  while IFS=$'\t' read -r method a us; do
    acc[$method,$gap]=$a
    solve[$method,$gap]=$us
  done < <("$vref" eval --dataset "$work/g$gap.jsonl" --beta 2500 --json \
    $(printf -- '--method %s ' "${methods[@]}") |
    python3 -c 'import json,sys
for l in sys.stdin:
    r = json.loads(l)
    print("%s\t%.3f\t%.0f" % (r["method"], r["accuracy"], r["mean_solve_us"]))')
done

printf '| method |'; for g in "${gaps[@]}"; do printf ' gap %s |' "$g"; done; echo
printf '|---|'; for _ in "${gaps[@]}"; do printf -- '---|'; done; echo
for m in "${methods[@]}"; do
  printf '| %s |' "$m"
  for g in "${gaps[@]}"; do
    cell=${acc[$m,$g]}
    if [[ -n "${published[$m,$g]:-}" ]]; then cell="$cell (${published[$m,$g]})"; fi
    printf ' %s |' "$cell"
  done
  echo
done
echo
echo "Mean solve time per scene at gap 90 (affinities + solve + Hungarian, one thread):"
for m in "${methods[@]}"; do echo "- $m: ${solve[$m,90]} us"; done
