#!/usr/bin/env bash
# Makes `vref match` frame folders of one BOP scene: OUT/robot (image 0)
# and OUT/human (image 1), each rgb.jpg, depth.png and a camera.json from
# scene_camera.json (cam_K, depth_scale).
#   bash tools/bop-frames.sh ../shared/data/bop/table/test/000003 OUT
set -euo pipefail
scene=$1 out=$2
for pair in 0:robot 1:human; do
  image=${pair%%:*} who=${pair#*:}
  mkdir -p "$out/$who"
  printf -v name '%06d' "$image"
  cp "$scene/rgb/$name.jpg" "$out/$who/rgb.jpg"
  cp "$scene/depth/$name.png" "$out/$who/depth.png"
  python3 - "$scene/scene_camera.json" "$image" "$out/$who/camera.json" <<'PY'
import json, struct, sys
camera = json.load(open(sys.argv[1]))[sys.argv[2]]
k = camera["cam_K"]
depth = open(sys.argv[3].replace("camera.json", "depth.png"), "rb").read(24)
width, height = struct.unpack(">II", depth[16:24])
json.dump({"fx": k[0], "fy": k[4], "cx": k[2], "cy": k[5], "width": width, "height": height,
           "depth_scale_mm": camera.get("depth_scale", 1.0)}, open(sys.argv[3], "w"))
PY
done
