#!/usr/bin/env bash
# `vref match` on real captures against themselves seen from elsewhere:
# every OSD learn frame (a Kinect) as the robot's view, and the same
# readings seen by a virtual camera walked YAW degrees around the table
# as the person's (`reproject` example: the real noise, holes and flying
# pixels; not a second sensor). Each person-side object's answer against
# the robot segment most of its pixels came from, and an `ok` answer also
# by physical object (OSD's labels: the two segments mostly one object, a
# piece of it will do); a row per yaw.
#
#   bash tools/reprojected-pairs.sh [--scale S] [--sensor SEED [--noise K]] [--move M] [YAW...]
#
# YAW defaults to -45 -30 -15 15 30 45. `--scale S` gives the person's
# camera an image S times the frame's each way, `--sensor SEED` a second
# sensor's own depth noise (K times the frame's) and colour response (the
# `reproject` example's header says which). `--move M` moves one object
# M metres along the table before the person looks; its own answers are
# counted in the last column too (frames where no object can move to a
# free place are left out).
#
# Needs `cargo build --release -p vref --bins` first.
set -euo pipefail
cd "$(dirname "$0")/.."
. tools/need-vref.sh
data=${VREF_DATA:-../shared/data}
options=()
while [ $# -gt 0 ]; do
  case $1 in
    --scale|--sensor|--noise|--move) options+=("$1" "$2"); shift 2 ;;
    *) break ;;
  esac
done
yaws=("$@")
[ ${#yaws[@]} -gt 0 ] || yaws=(-45 -30 -15 15 30 45)
cargo build --release -q -p vref-perception --example reproject
reproject=target/release/examples/reproject
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
moving=0
[[ " ${options[*]} " == *" --move "* ]] && moving=1
header="| yaw | frames | person-side objects | with a true partner | ok right | ok wrong | ok, other object | ambiguous right | ambiguous wrong | no partner (of them with a true one) |"
rule="|---|---|---|---|---|---|---|---|---|---|"
if [ $moving = 1 ]; then
  header="$header moved object seen: ok right / ok wrong / ambiguous right / ambiguous wrong / no partner |"
  rule="$rule---|"
fi
echo "$header"
echo "$rule"
for yaw in "${yaws[@]}"; do
  for frame in "$data"/osd/learn/*/; do
    out=$work/$yaw-$(basename "$frame")
    "$reproject" make "$frame" "$out" "$yaw" "${options[@]}" 2>/dev/null || continue
    "$vref" match "$out/robot" "$out/human" --json --labels-out "$out/labels" \
      > "$out/answers.jsonl" 2>/dev/null
    "$reproject" score "$out"
  done | python3 -c '
import json, sys
rows = [json.loads(l) for l in sys.stdin]
n = lambda k: sum(r.get(k, 0) for r in rows)
line = "| %s | %d | %d | %d | %d | %d | %d | %d | %d | %d (%d) |" % (sys.argv[1], len(rows), n("objects"),
      n("with_truth"), n("ok_right"), n("ok_wrong"), n("ok_other_object"), n("ambiguous_right"), n("ambiguous_wrong"),
      n("no_partner_with_truth") + n("no_partner_without_truth"), n("no_partner_with_truth"))
if sys.argv[2] == "1":
    m = lambda k: n("moved_" + k)
    line += " %d: %d / %d / %d / %d / %d |" % (m("seen"), m("ok_right"), m("ok_wrong"), m("ambiguous_right"),
        m("ambiguous_wrong"), m("no_partner_with_truth") + m("no_partner_without_truth"))
print(line)' "$yaw" "$moving"
done
