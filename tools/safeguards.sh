#!/usr/bin/env bash
# What each safeguard of an `ok` answer costs and buys, on the training
# files only (docs/method.md, "When an answer is ok"): for each family, the
# right partners and wrong partners answered `ok` with every safeguard on,
# then with one turned off at a time, and the unrelated training views'
# `ok` share. A safeguard's cost is the right partners it keeps from `ok`
# (they become `ambiguous`, or "no partner" for the abstention); what it
# buys is the wrong partners it keeps from `ok`. Statuses are the
# matcher's (`vref eval --answers`, exact tier).
#
#   bash tools/carryover-data.sh && bash tools/safeguards.sh
#
# Needs `cargo build --release -p vref -p vref-research --bins --examples` first.
set -euo pipefail
cd "$(dirname "$0")/.."
. tools/need-vref.sh
dir=${VREF_CARRY_DIR:-target/carry}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# name|settings that turn the safeguard off (key = value, ;-separated)
variants=(
  "all on|"
  "ambiguity threshold off|ambiguity_threshold = 0.0"
  "fit test off|fit_limit = inf"
  "coincidence cap off|chance_rule = false"
  "abstention off|abstain_share = 0.0;abstain_share_evident = 0.0"
)
config_with() {
  python3 - "$1" "$2" <<'PY'
import re, sys
text = open("config/vref.toml").read()
for item in filter(None, (s.strip() for s in sys.argv[1].split(";"))):
    key = item.split("=")[0].strip()
    text, n = re.subn(rf"(?m)^{re.escape(key)}\s*=.*$", item, text, count=1)
    if n != 1:
        sys.exit(f"safeguards.sh: no {key} in config/vref.toml")
open(sys.argv[2], "w").write(text)
PY
}
families=(
  "sim moi|$(echo "$dir"/moi10{0..9}.jsonl)"
  "sim mrc|$(echo "$dir"/mrc10{0..9}.jsonl)"
  "moi-ext|$dir/moi-ext-train.jsonl"
  "mrc-ext|$dir/mrc-ext-train.jsonl"
  "bop table|$dir/bop-table-train.jsonl"
  "bop floor|$dir/bop-floor-train.jsonl"
  "unrelated|$(echo "$dir"/null-train/*.jsonl)"
)
for v in "${variants[@]}"; do
  name=${v%%|*}
  config_with "${v#*|}" "$work/vref.toml"
  for f in "${families[@]}"; do
    family=${f%%|*}
    for file in ${f#*|}; do
      [ -s "$file" ] || continue
      "$vref" eval --dataset "$file" --method rigid --config "$work/vref.toml" \
        --answers "$work/a.jsonl" --json > /dev/null
      sed "s/^/$family|$name|/" "$work/a.jsonl"
    done
  done
done | python3 -c '
import json, sys
from collections import defaultdict
count = defaultdict(lambda: [0, 0, 0, 0])  # right partners, right ok, wrong ok, answers
variants, families = [], []
for line in sys.stdin:
    family, variant, row = line.split("|", 2)
    r = json.loads(row)
    c = count[family, variant]
    ok = r["status"] == "ok"
    c[0] += r["correct"] and r["matched"]
    c[1] += ok and r["correct"]
    c[2] += ok and not r["correct"]
    c[3] += 1
    variants += [variant] if variant not in variants else []
    families += [family] if family not in families else []
print("| family | " + " | ".join(variants) + " |")
print("|---|" + "---|" * len(variants))
for f in families:
    cells = []
    for v in variants:
        right, right_ok, wrong_ok, answers = count[f, v]
        if f == "unrelated":
            cells.append(f"{wrong_ok} ok of {answers} ({100 * wrong_ok / max(1, answers):.2f}%)")
        else:
            cells.append(f"{right_ok} right / {wrong_ok} wrong ok")
    print(f"| {f} | " + " | ".join(cells) + " |")
'
