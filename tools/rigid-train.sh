#!/usr/bin/env bash
# Evaluates `rigid` with some `[matching.rigid]` settings on every training
# file of docs/method.md ("How each data set is used": vref-sim seeds
# 100-109 of both presets, lines 1-20 of the external sets, BOP scenes
# 000000-000005) and prints, per family, mean accuracy, mean and lowest
# precision and mean and largest ECE over its files. Unnamed settings keep
# the values of config/vref.toml. Never reads a reporting file.
#
#   bash tools/rigid-train.sh 'noise_prior = 4.5\nunmatched_cost = 5.0'
#
# Needs `cargo build --release -p vref -p vref-research --bins --examples` and
# `bash tools/carryover-data.sh` first (files in ${VREF_CARRY_DIR:-target/carry};
# the BOP families are left out when their training files are not there).
set -euo pipefail
cd "$(dirname "$0")/.."
. tools/need-vref.sh
dir=${VREF_CARRY_DIR:-target/carry}
settings=${1:-}
config=$(mktemp)
trap 'rm -f "$config"' EXIT
python3 - "$settings" "$config" <<'PY'
import re, sys
settings, out = sys.argv[1].encode().decode("unicode_escape"), sys.argv[2]
text = open("config/vref.toml").read()
head, sep, rest = text.partition("[matching.rigid]")
if not sep:
    sys.exit("rigid-train.sh: config/vref.toml has no [matching.rigid] table")
body, nxt, tail = rest.partition("\n[")
for line in filter(None, (l.strip() for l in settings.splitlines())):
    key = line.split("=")[0].strip()
    body, n = re.subn(rf"(?m)^{re.escape(key)}\s*=.*$", line, body, count=1)
    if n == 0:
        body += "\n" + line + "\n"
open(out, "w").write(head + sep + body + nxt + tail)
PY
family() {
  local name=$1 beta=$2
  shift 2
  for f in "$@"; do
    [ -s "$f" ] || return 0
    "$vref" eval --dataset "$f" --method rigid --json --config "$config" --beta "$beta"
  done | python3 -c "
import json, sys
r = [json.loads(l) for l in sys.stdin]
if r:
    a = [x['accuracy'] for x in r]; p = [x['precision'] for x in r]; e = [x['ece'] for x in r]
    print('%-10s accuracy %.4f, precision mean %.4f lowest %.3f, ECE mean %.4f largest %.3f'
          % (sys.argv[1], sum(a) / len(a), sum(p) / len(p), min(p), sum(e) / len(e), max(e)))" "$name"
}
echo "settings: $(printf '%b' "${settings:-defaults}" | tr '\n' ' ')"
family sim-moi 0.01 $(for s in $(seq 100 109); do echo "$dir/moi$s.jsonl"; done)
family sim-mrc 0.1 $(for s in $(seq 100 109); do echo "$dir/mrc$s.jsonl"; done)
family moi-ext 0.01 "$dir/moi-ext-train.jsonl"
family mrc-ext 0.1 "$dir/mrc-ext-train.jsonl"
family bop-table 0.01 "$dir/bop-table-train.jsonl"
family bop-floor 0.1 "$dir/bop-floor-train.jsonl"
