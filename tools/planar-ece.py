"""Calibration on nearly planar layouts (docs/method.md, "Nearly planar
layouts"): each scene's human view is nearly planar when its objects'
least spread (the square root of the smallest eigenvalue of their
positions' covariance) is under FLAT (0.15) of their middle spread. For
each dataset file, `vref eval --answers` is run with its features and
without them, and ECE and the wrong `ok` answers are given for the nearly
planar scenes and the others. Beside each ECE, its sampling floor: the
mean ECE of answers exactly as right as their confidences say, at the
same confidences (200 draws, seeded), which a few hundred answers cannot
go below.

    python3 tools/planar-ece.py VREF FILE.jsonl...
"""

import json
import math
import os
import random
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from ece import ece  # noqa: E402
from strip_features import without_features  # noqa: E402

FLAT = 0.15


def spreads(points):
    """Eigenvalues of the covariance of 3-D points, ascending (closed form
    for a symmetric 3 x 3 matrix)."""
    n = len(points)
    mean = [sum(p[k] for p in points) / n for k in range(3)]
    c = [[sum((p[a] - mean[a]) * (p[b] - mean[b]) for p in points) / n for b in range(3)]
         for a in range(3)]
    p1 = c[0][1] ** 2 + c[0][2] ** 2 + c[1][2] ** 2
    q = (c[0][0] + c[1][1] + c[2][2]) / 3
    if p1 == 0:
        return sorted(c[k][k] for k in range(3))
    p2 = sum((c[k][k] - q) ** 2 for k in range(3)) + 2 * p1
    p = math.sqrt(p2 / 6)
    b = [[(c[a][k] - (q if a == k else 0)) / p for k in range(3)] for a in range(3)]
    det = (b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1])
           - b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0])
           + b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]))
    r = max(-1.0, min(1.0, det / 2))
    phi = math.acos(r) / 3
    big = q + 2 * p * math.cos(phi)
    small = q + 2 * p * math.cos(phi + 2 * math.pi / 3)
    return sorted([small, 3 * q - big - small, big])


def flat(pair):
    points = [o["position"] for o in pair["human"]["objects"]]
    if len(points) < 3:
        return False
    least, middle, _ = spreads(points)
    return math.sqrt(max(least, 0.0)) < FLAT * math.sqrt(max(middle, 1e-30))


def sampling_floor(confidences, draws=200):
    rng = random.Random(1)
    return sum(ece([(c, rng.random() < c) for c in confidences])
               for _ in range(draws)) / draws


def cell(rows):
    if not rows:
        return "-"
    wrong_ok = sum(r["status"] == "ok" and not r["correct"] for r in rows)
    return "%.3f, floor %.3f (%d answers, %d wrong ok)" % (
        ece([(r["confidence"], r["correct"]) for r in rows]),
        sampling_floor([r["confidence"] for r in rows]), len(rows), wrong_ok)


def main():
    vref, files = sys.argv[1], sys.argv[2:]
    print("| file | features | nearly planar scenes | ECE there | ECE elsewhere |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for path in files:
            pairs = [json.loads(line) for line in open(path)]
            is_flat = [flat(p) for p in pairs]
            bare = os.path.join(work, "bare.jsonl")
            without_features(path, bare)
            for label, data in (("with", path), ("without", bare)):
                answers = os.path.join(work, "answers.jsonl")
                subprocess.run([vref, "eval", "--dataset", data, "--method", "rigid",
                                "--answers", answers], check=True, stdout=subprocess.DEVNULL)
                rows = [json.loads(line) for line in open(answers)]
                there = [r for r in rows if is_flat[r["scene"]]]
                elsewhere = [r for r in rows if not is_flat[r["scene"]]]
                name = os.path.basename(path).removesuffix(".jsonl")
                print("| %s | %s | %d of %d | %s | %s |" % (
                    name, label, sum(is_flat), len(pairs), cell(there), cell(elsewhere)))


if __name__ == "__main__":
    main()
