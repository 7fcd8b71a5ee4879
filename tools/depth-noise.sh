#!/usr/bin/env bash
# The per-reading depth noise each camera's frames show
# (`vref_perception::pixel_noise`, what `vref match --noise frame` uses),
# against what ../shared/data says of them: OSD learn (a Kinect; no law
# stated) and both views of every rendered BOP scene (PROVENANCE: 0.0025
# z^2 robot, 0.02 z^2 headset on the table, 0.01 on the floor).
#   bash tools/depth-noise.sh
set -euo pipefail
cd "$(dirname "$0")/.."
data=${VREF_DATA:-../shared/data}
cargo build --release -q -p vref-perception --example depth_noise
noise=target/release/examples/depth_noise
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
summary() {
  sort -g | awk -v name="$1" '{v[NR] = $1} END {
    printf "| %s | %d | %.5f | %.5f | %.5f |\n", name, NR, v[1], v[int((NR + 1) / 2)], v[NR] }'
}
echo "| frames | count | c, least | median | most |"
echo "|---|---|---|---|---|"
"$noise" "$data"/osd/learn/*/ | cut -f2 | summary "OSD learn (Kinect)"
for preset in table floor; do
  for scene in "$data/bop/$preset/test/"*/; do
    bash tools/bop-frames.sh "$scene" "$work/$preset-$(basename "$scene")"
  done
  "$noise" "$work/$preset"-*/robot | cut -f2 | summary "BOP $preset, robot"
  "$noise" "$work/$preset"-*/human | cut -f2 | summary "BOP $preset, headset"
done
