#!/usr/bin/env python3
"""Where the `ok` answers on a BOP import point, under the true camera motion.

    python tools/bop-ok-places.py DATASET.jsonl ANSWERS.jsonl BOP_DIR

DATASET.jsonl is `vref import bop BOP_DIR [--segment] --out ...`; ANSWERS
is `vref eval --dataset DATASET.jsonl --method rigid --answers ...`. For
every `ok` answer it moves the human object into the robot camera's frame
with the scenes' own camera poses (scene_camera.json: image 0 the robot,
1 the headset, as the import's defaults) and prints how far the robot
object the answer names is from it, in centimetres, for the answers the
dataset's truth calls right and those it calls wrong. With vref's own
segments the truth is an instance overlapping a segment by IoU 0.5: a
segment short of that has no truth, and an answer about it is "wrong"
even where it names the robot segment at the same place.
"""
import json
import sys
from pathlib import Path

import numpy as np


def pose(cams, image):
    rotation = np.array(cams[image]["cam_R_w2c"], dtype=float).reshape(3, 3)
    return rotation, np.array(cams[image]["cam_t_w2c"], dtype=float) / 1000.0


def main(dataset, answers, bop):
    scenes = [json.loads(line) for line in open(dataset)]
    apart = {True: [], False: []}
    for line in open(answers):
        a = json.loads(line)
        if a["status"] != "ok" or a.get("partner") is None:
            continue
        scene = scenes[a["scene"]]
        folder = scene["name"].split("/")[-1]
        cams = json.load(open(Path(bop) / "test" / folder / "scene_camera.json"))
        (r_robot, t_robot), (r_human, t_human) = pose(cams, "0"), pose(cams, "1")
        human = next(o for o in scene["human"]["objects"] if o["id"] == a["human_object"])
        robot = next(o for o in scene["robot"]["objects"] if o["id"] == a["partner"])
        world = r_human.T @ (np.array(human["position"]) - t_human)
        moved = r_robot @ world + t_robot
        apart[a["correct"]].append(100.0 * float(np.linalg.norm(np.array(robot["position"]) - moved)))
    for correct, name in ((True, "right"), (False, "wrong")):
        cm = sorted(apart[correct])
        if cm:
            print(f"ok, {name} by the truth: {len(cm)}; cm apart: median {np.median(cm):.1f}, "
                  f"max {cm[-1]:.1f}, all {', '.join(f'{c:.1f}' for c in cm)}")
        else:
            print(f"ok, {name} by the truth: 0")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
