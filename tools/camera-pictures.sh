#!/usr/bin/env bash
# The camera-only pictures of README.md and docs/perception.md: vref's own
# segments of a real OSD scene, and `vref match` on a rendered BOP scene's
# two views (robot, headset) with vref's own segments.
#   bash tools/camera-pictures.sh        (after cargo build --release)
set -euo pipefail
cd "$(dirname "$0")/.."
vref=target/release/vref
data=${VREF_DATA:-../shared/data}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
osd=$data/osd/learn/learn36
"$vref" segment --rgb "$osd/rgb.png" --depth "$osd/depth.png" --camera "$data/osd/camera.json" \
  --out "$work/learn36.png" --overlay docs/camera-osd-learn36.png
bash tools/bop-frames.sh "$data/bop/table/test/000003" "$work/table-000003"
"$vref" match "$work/table-000003/robot" "$work/table-000003/human" \
  --viz docs/camera-match-table-000003.png > /dev/null
