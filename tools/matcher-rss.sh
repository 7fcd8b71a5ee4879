#!/usr/bin/env bash
# Peak resident memory of the matcher serving N objects per view: both feeds
# replay `vref scenes --preset rigid --objects N` scenes at 30 Hz, a query
# every 50 ms makes the matcher solve, and VmRSS is read every 50 ms.
# Usage: bash tools/matcher-rss.sh [N] [SECONDS]   (after cargo build --release)
set -euo pipefail
cd "$(dirname "$0")/.."
N=${1:-128}
SECONDS_TO_RUN=${2:-10}
R=target/release
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT
sed -e "s|^prefix = \"vref_\"|prefix = \"rss${N}_$$_\"\nroot_path = \"$work/iox/\"|" config/vref.toml > "$work/vref.toml"
$R/vref scenes --preset rigid --objects "$N" --count 4 --seed 1 --out "$work/scenes.jsonl"
$R/vref-matcher --config "$work/vref.toml" 2>"$work/matcher.log" &
matcher=$!
sleep 0.5
for feed in vref-perception-feed vref-gesture-feed; do
  $R/$feed --config "$work/vref.toml" --source "dataset:$work/scenes.jsonl" --hold 1s 2>/dev/null &
done
peak=0
answered=0
end=$((SECONDS + SECONDS_TO_RUN))
while [ $SECONDS -lt $end ]; do
  # Any answer counts (exit 0, or 3-5 for bad_request, not_ready, stale);
  # 1 is no answer in time.
  code=0
  $R/vref query --config "$work/vref.toml" --human-object 0 --timeout 500ms --json >/dev/null 2>&1 || code=$?
  if [ "$code" -eq 0 ] || [ "$code" -ge 3 ]; then
    answered=$((answered + 1))
  fi
  rss=$(awk '/VmRSS/{print $2}' "/proc/$matcher/status")
  [ "$rss" -gt "$peak" ] && peak=$rss
  sleep 0.05
done
echo "objects=$N answered_queries=$answered matcher_peak_rss_kb=$peak"
