#!/usr/bin/env bash
# Size of a recording of the demo's world: starts the matcher and both
# synthetic feeds under a root path and prefix of their own, records them
# for SECONDS with `vref record` as MCAP and as .vrec side by side, and
# prints one JSON object per format: bytes, seconds, MB per minute.
#
#   bash tools/recording-size.sh [SECONDS]     (default 60; after cargo build --release)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
R=target/release
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT
mkdir -p "$work/iox"
printf '[ipc]\nroot_path = "%s/iox/"\nprefix = "rec%s_"\n' "$work" "$$" > "$work/vref.toml"
for bin in vref-matcher vref-perception-feed vref-gesture-feed; do
  "$R/$bin" --config "$work/vref.toml" 2>"$work/$bin.log" &
done
# Ready when the matcher answers (bounded: 30 tries, about 15 s).
for _ in $(seq 30); do
  "$R/vref" query --config "$work/vref.toml" --latest-gesture --json >/dev/null 2>&1 && break
  sleep 0.5
done
"$R/vref" record --config "$work/vref.toml" --out "$work/demo.mcap" --duration "${seconds}s" 2>/dev/null >/dev/null &
mcap=$!
"$R/vref" record --config "$work/vref.toml" --out "$work/demo.vrec" --duration "${seconds}s" 2>/dev/null >/dev/null
wait "$mcap"
for file in demo.mcap demo.vrec; do
  bytes=$(stat -c %s "$work/$file")
  python3 -c 'import json,sys
b, s, f = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
print(json.dumps({"format": f.split(".")[1], "bytes": b, "seconds": s, "mb_per_minute": round(b / 1e6 * 60 / s, 2)}))' \
    "$bytes" "$seconds" "$file"
done
