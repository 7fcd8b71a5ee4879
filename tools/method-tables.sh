#!/usr/bin/env bash
# Regenerates the JSON behind docs/method-results.md's tables: every method on every
# reporting set (held out from every choice of constants), one `vref eval
# --json` line per method and set, and the share of `ok` answers on views
# with nothing in common.
#   docs/results/method-vrefsim.json   moi1-5 (beta 0.01), mrc1-5 (beta 0.1)
#   docs/results/method-external.json  lines 21-40 of moi-ext (0.01), mrc-ext (0.1)
#   docs/results/method-bop.json       rendered scenes 000006-000011, table (0.01), floor (0.1)
#   docs/results/coincidence.json      rigid on unrelated views made from reporting files
# beta is each family's spatial bandwidth (external PROVENANCE.md); rigid
# does not use it. Needs `cargo build --release -p vref -p vref-research --bins --examples` and
# `bash tools/carryover-data.sh` first. Only reporting files are read.
set -euo pipefail
cd "$(dirname "$0")/.."
. tools/need-vref.sh
dir=${VREF_CARRY_DIR:-target/carry}
out=${VREF_RESULTS_DIR:-docs/results}
mkdir -p "$out"
beta() { case $1 in moi*|bop-table*) echo 0.01 ;; *) echo 0.1 ;; esac; }
run() {
  for set in "$@"; do
    [ -s "$dir/$set.jsonl" ] || continue
    "$vref" eval --dataset "$dir/$set.jsonl" --beta "$(beta "$set")" --json 2>/dev/null
  done
}
run moi1 moi2 moi3 moi4 moi5 mrc1 mrc2 mrc3 mrc4 mrc5 > "$out/method-vrefsim.json"
run moi-ext-report mrc-ext-report > "$out/method-external.json"
run bop-table-report bop-floor-report > "$out/method-bop.json"
: > "$out/coincidence.json"
for file in "$dir"/null-report/*.jsonl; do
  answers=$(mktemp)
  "$vref" eval --dataset "$file" --method rigid --answers "$answers" --json > /dev/null 2>&1
  python3 - "$file" "$answers" >> "$out/coincidence.json" <<'PY'
import json, os, sys
rows = [json.loads(line) for line in open(sys.argv[2])]
ok = sum(1 for r in rows if r["status"] == "ok")
partner = sum(1 for r in rows if r["matched"])
print(json.dumps({"dataset": os.path.basename(sys.argv[1]), "answers": len(rows),
                  "partners": partner, "ok": ok, "ok_share": ok / max(1, len(rows))}))
PY
  rm -f "$answers"
done
