#!/usr/bin/env bash
# Re-measures every figure the README and docs/ publish: runs the committed
# commands, writes their JSON under docs/results/ (one file per table,
# named in the table), then rewrites the marked tables of README.md and
# docs/*.md from those files (tools/tables.py).
#
#   bash tools/reproduce.sh            # the full runs (about an hour)
#   bash tools/reproduce.sh --quick    # shorter runs of the same commands (< 15 min once built)
#   bash tools/reproduce.sh --tables   # only rewrite the tables from docs/results/
#
# --quick shortens the timed runs (soak 60 s instead of 10 min, benches
# 10 s instead of 30 s, fewer solver repeats) and skips the noise sweeps;
# the accuracy tables are the same in both modes. docs/results/run.json
# says which mode, commit and machine wrote the files.
#
# Needs: a Rust toolchain (it builds the release binaries if needed),
# python3 3.11+ with venv (the Python client's bench, in
# target/python-venv as tools/test.sh makes it), and the shared data at
# ../shared/data (or VREF_DATA).
set -euo pipefail
cd "$(dirname "$0")/.."

mode=full
case "${1:-}" in
  --quick) mode=quick ;;
  --tables) python3 tools/tables.py README.md docs/*.md; exit 0 ;;
  "") ;;
  -h | --help) sed -n 2,20p "$0"; exit 0 ;;
  *) echo "reproduce.sh: unknown argument '$1' (--quick, --tables or nothing)" >&2; exit 2 ;;
esac

data=${VREF_DATA:-../shared/data}
out=docs/results
work=target/reproduce
export VREF_CARRY_DIR=$work/carry VREF_BOP_DIR=$work/bop VREF_EXTERNAL_DIR=$data/external
vref=target/release/vref
mkdir -p "$out" "$work/bop"
for need in "$data/bop/table" "$data/bop/floor" "$data/external" "$data/cmu_house"; do
  [ -d "$need" ] || { echo "reproduce.sh: $need is missing (set VREF_DATA)" >&2; exit 2; }
done

started=$(date +%s)
step() { echo "== $(( $(date +%s) - started )) s: $*" >&2; }
if [ "$mode" = quick ]; then
  bench_s=10s soak_s=60s solver_repeats=10 solver_tiers="--tier live" solver_sizes=8,16,32,64
else
  bench_s=30s soak_s=10m solver_repeats=30 solver_tiers="--tier live --tier exact" solver_sizes=8,16,32,64,128
fi

step "building (release)"
cargo build --release --locked --workspace -q
cargo build --release --locked -p vref-research --examples -q

python3 - "$mode" > "$out/run.json" <<'PY'
import json, os, subprocess, sys, time
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
# Changes to the code, not to what this run writes (docs/, README.md; this
# very file is already truncated by the redirection).
dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", "--", ".", ":(exclude)docs", ":(exclude)README.md"],
                       capture_output=True, text=True).stdout.strip()
print(json.dumps({"mode": sys.argv[1], "date": time.strftime("%Y-%m-%d"), "commit": commit + ("+changes" if dirty else ""),
                  "cpu": cpu, "cores": os.cpu_count(), "load_at_start": round(os.getloadavg()[0], 2)}))
PY

step "BOP scenes through the perception front end"
for preset in table floor; do
  file=$work/bop/bop-$preset.jsonl
  "$vref" import bop "$data/bop/$preset" --out "$file" 2>/dev/null
  "$vref" eval --dataset "$file" --json > "$out/bop-$preset.json"
  sed -n 1,6p "$file" > "$work/bop-$preset-000000-000005.jsonl"
  sed -n 7,12p "$file" > "$work/bop-$preset-000006-000011.jsonl"
  for half in 000000-000005 000006-000011; do
    "$vref" eval --dataset "$work/bop-$preset-$half.jsonl" --json
  done > "$out/bop-$preset-halves.json"
done
"$vref" bench perception --dataset "$data/bop" --repeats "$([ "$mode" = quick ] && echo 5 || echo 20)" --json \
  > "$out/perception-bench.json"

step "camera only: BOP scenes with vref's own segments, OSD segmentation scores, pictures"
for preset in table floor; do
  file=$work/bop/bop-$preset-segment.jsonl
  "$vref" import bop "$data/bop/$preset" --segment --out "$file" 2>/dev/null
  # The reporting scenes (tools/carryover-data.sh's split); rigid only.
  grep -E '"name": *"[^"]*0000(0[6-9]|1[01])"' "$file" > "$work/bop-$preset-segment-report.jsonl" || true
  "$vref" eval --dataset "$work/bop-$preset-segment-report.jsonl" --method rigid --json
done > "$out/bop-segment.json"
"$vref" bench segment --dataset "$data/osd/learn" --json > "$out/segment-osd-learn.json"
bash tools/camera-pictures.sh

step "data sets of the method tables (tools/carryover-data.sh)"
bash tools/carryover-data.sh
step "every method on every held-out set (tools/method-tables.sh)"
bash tools/method-tables.sh

step "CMU House, the published protocol"
: > "$out/cmu-house.json"
for gap in 0 10 20 30 40 50 60 70 80 90; do
  "$vref" import cmu-house "$data/cmu_house" --gap "$gap" --delaunay --out "$work/cmu-g$gap.jsonl" 2>/dev/null
  "$vref" eval --dataset "$work/cmu-g$gap.jsonl" --beta 2500 --json \
    --method appearance --method sm --method rrwm --method paper 2>/dev/null |
    python3 -c 'import json,sys
for line in sys.stdin:
    d = json.loads(line); d["gap"] = int(sys.argv[1]); print(json.dumps(d))' "$gap" >> "$out/cmu-house.json"
done

for gap in 0 50 90; do
  file=$work/cmu-keep25-gap$gap.jsonl
  "$vref" import cmu-house "$data/cmu_house" --gap "$gap" --delaunay --keep 25 --seed 1 --out "$file" 2>/dev/null
  "$vref" eval --dataset "$file" --beta 2500 --method rigid --method rrwm --json 2>/dev/null
done > "$out/cmu-house-keep25.json"

if [ "$mode" = full ]; then
  step "noise sweeps (moi)"
  "$vref" eval --sweep depth-noise --preset moi --out docs/sweep-depth-moi.png --json > "$out/sweep-depth-moi.json" 2>/dev/null
fi

step "solve time (vref bench solver)"
# shellcheck disable=SC2086
"$vref" bench solver --method rigid --method paper --method rrwm $solver_tiers \
  --sizes "$solver_sizes" --repeats "$solver_repeats" --json > "$out/bench-solver.jsonl"
# The same scenes with position noise near the objects' spacing at 64
# objects: no motion settles them, and rigid runs its whole search.
"$vref" bench solver --method rigid --tier live --sizes 16,32,64 --noise 0.02 \
  --repeats "$solver_repeats" --json > "$out/bench-solver-noisy.jsonl"

step "pictures"
"$vref" viz --dataset "$VREF_CARRY_DIR/moi1.jsonl" --scene moi-1-13 --method rigid --out docs/viz-moi-rigid.png 2>/dev/null

step "the demo"
"$vref" demo --json > "$out/demo.json"
step "query round trip (vref bench query --compare-idle, $bench_s)"
"$vref" bench query --objects 64 --duration "$bench_s" --compare-idle --json > "$out/bench-query.json"
printf '[scene]\ncapacity = 87\n\n[matcher]\nmethod = "paper"\ntier = "exact"\n' > "$work/slowest.toml"
"$vref" config check "$work/slowest.toml" > /dev/null
"$vref" bench query --config "$work/slowest.toml" --objects 87 --rate 100 --duration "$bench_s" --compare-idle --json \
  > "$out/bench-query-slowest.json"
"$vref" bench query --objects 32 --duration "$bench_s" --json > "$out/bench-query-32.json"
"$vref" bench query --objects 32 --duration "$bench_s" --with-viewer --json > "$out/bench-query-32-viewer.json"
step "remote round trip (vref bench remote, $bench_s)"
"$vref" bench remote --duration "$bench_s" --json > "$out/bench-remote.json"
step "ROS 2 latency (vref bench ros2, $bench_s; needs root and target/ros2-venv from tools/test.sh)"
if [ -x target/ros2-venv/bin/python ]; then
  "$vref" bench ros2 --seconds "${bench_s%s}" --json --python target/ros2-venv/bin/python \
    > "$out/bench-ros2.json"
else
  echo "reproduce.sh: target/ros2-venv is missing (bash tools/test.sh makes it): vref bench ros2 skipped" >&2
fi

step "Python client round trip"
venv=${VREF_VENV:-target/python-venv}
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check ./clients/python
"$venv/bin/python" -m vref_client.bench --duration "$bench_s" --bin-dir target/release --json > "$out/python-bench.json"

if [ "$mode" = full ]; then
  step "pygmtools on the solver bench's scenes"
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check pygmtools==0.6.0
  : > "$out/pygmtools.jsonl"
  for n in 8 16 32 64; do
    "$vref" scenes --preset rigid --objects "$n" --count 8 --seed 1 --out "$work/rigid$n.jsonl" 2>/dev/null
    repeats=$([ "$n" = 64 ] && echo 1 || echo 3)
    for params in algorithms defaults; do
      "$venv/bin/python" tools/pygmtools_bench.py --dataset "$work/rigid$n.jsonl" --repeats "$repeats" \
        --params "$params" $([ "$params" = defaults ] && echo --method rrwm) --json >> "$out/pygmtools.jsonl"
    done
  done
fi
step "vref's side of the pygmtools comparison"
"$vref" bench solver --method rrwm --method sm --tier exact --tier live \
  --sizes 8,16,32,64 --repeats "$solver_repeats" --json > "$out/bench-solver-pygmtools.jsonl"
"$vref" bench plot --solver "$out/bench-solver-pygmtools.jsonl" --pygmtools "$out/pygmtools.jsonl" \
  --out docs/solve-time.png 2>/dev/null

step "recording size"
bash tools/recording-size.sh "$([ "$mode" = quick ] && echo 20 || echo 60)" > "$out/recording-size.json"

step "soak ($soak_s)"
"$vref" soak --duration "$soak_s" --json > "$out/soak.json"

step "tables"
python3 tools/tables.py README.md docs/*.md
step "done ($mode); the files are in $out/"
