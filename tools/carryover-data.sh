#!/usr/bin/env bash
# Writes every data set `rigid`'s constants are chosen or reported on into
# ${VREF_CARRY_DIR:-target/carry} (docs/method.md, "How each data set is
# used"), and prints nothing else:
#   training:  moi100..moi109, mrc100..mrc109 (vref-sim, 30 scenes each),
#              moi-ext-train, mrc-ext-train (lines 1-20 of the external sets),
#              bop-table-train, bop-floor-train (scenes 000000-000005), and
#              unrelated views made from the training files (null-train/);
#   reporting: moi1..moi5, mrc1..mrc5, moi-ext-report, mrc-ext-report
#              (lines 21-40), bop-table-report, bop-floor-report (scenes
#              000006-000011), and unrelated views made from reporting files
#              (null-report/).
# The BOP files are taken from ${VREF_BOP_DIR:-../data} (bop-table.jsonl,
# bop-floor.jsonl: the perception front end's import of the rendered
# scenes) when they are there.
# Needs `cargo build --release -p vref -p vref-research --bins --examples` first.
set -euo pipefail
cd "$(dirname "$0")/.."
. tools/need-vref.sh
dir=${VREF_CARRY_DIR:-target/carry}
external=${VREF_EXTERNAL_DIR:-../shared/data/external}
bop=${VREF_BOP_DIR:-../data}
mkdir -p "$dir"
for preset in moi mrc; do
  for seed in $(seq 100 109) 1 2 3 4 5; do
    [ -s "$dir/$preset$seed.jsonl" ] ||
      "$vref" scenes --preset "$preset" --count 30 --seed "$seed" --out "$dir/$preset$seed.jsonl" 2>/dev/null
  done
  head -n 20 "$external/$preset-ext.jsonl" > "$dir/$preset-ext-train.jsonl"
  tail -n +21 "$external/$preset-ext.jsonl" > "$dir/$preset-ext-report.jsonl"
done
for family in table floor; do
  file="$bop/bop-$family.jsonl"
  [ -s "$file" ] || continue
  grep -E '"name": *"[^"]*00000[0-5]"' "$file" > "$dir/bop-$family-train.jsonl" || true
  grep -E '"name": *"[^"]*0000(0[6-9]|1[01])"' "$file" > "$dir/bop-$family-report.jsonl" || true
done
train=("$dir"/moi100.jsonl "$dir"/mrc100.jsonl "$dir"/moi-ext-train.jsonl "$dir"/mrc-ext-train.jsonl)
report=("$dir"/moi1.jsonl "$dir"/mrc1.jsonl "$dir"/moi-ext-report.jsonl "$dir"/mrc-ext-report.jsonl)
for family in table floor; do
  [ -s "$dir/bop-$family-train.jsonl" ] && train+=("$dir/bop-$family-train.jsonl")
  [ -s "$dir/bop-$family-report.jsonl" ] && report+=("$dir/bop-$family-report.jsonl")
done
target/release/examples/unrelated 11 "$dir/null-train" "${train[@]}"
target/release/examples/unrelated 12 "$dir/null-report" "${report[@]}"
