#!/usr/bin/env python3
"""Fits the `rigid` method's confidence calibration on training files.

    python3 tools/fit-calibration.py [--settings FILE] [--vref target/release/vref] [--positions] TRAIN.jsonl...

Runs `vref eval --method rigid --answers` on every file with the
calibration switched to the identity (bias 0, slope 1, other terms 0), so
that each answer's confidence is its raw share (abstention, decided on raw
shares, stays as configured; `--settings` holds further `[matching.rigid]`
lines), then fits the logistic map

    p = sigmoid(bias + slope * logit(raw) + no_partner_shift * [no partner]
                + partner_margin * [partner] * g + none_margin * [no partner] * g)

(g: the best motion's margin over chance, clamped to [-3, 3]) by Newton's
method on the log loss, every file weighing the same (a file of many
answers does not outweigh a family of few). It prints the
`[matching.rigid.calibration]` constants, which go into
crates/vref-match/src/calibration.rs (the defaults) and config/vref.toml,
and each file's training ECE, beside its sampling floor: the mean ECE of
perfectly calibrated answers at the same confidences (200 draws of right
or wrong, each right with its confidence), which no map can go below.
With `--positions` every feature is removed from the files first: the map
fitted to answers that rest on positions alone (docs/method.md, "When an
answer is ok"). Only training files may be given: the
figures of docs/method.md come from others (tools/carryover-data.sh lists
which are which).
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ece import ece  # noqa: E402
from linear import solve  # noqa: E402
import strip_features  # noqa: E402

EPS = 1e-6
CAP = 3.0


def logit(p):
    p = min(max(p, EPS), 1 - EPS)
    return math.log(p / (1 - p))


def features(row):
    g = row.get("margin")
    g = CAP if g is None else max(-CAP, min(CAP, g))
    none = 0.0 if row["matched"] else 1.0
    return (1.0, logit(row["confidence"]), none, (1 - none) * g, none * g)


def without_features(path, work):
    """A copy of dataset file `path` with every object's feature removed."""
    out = os.path.join(work, "positions-" + os.path.basename(path))
    strip_features.without_features(path, out)
    return out


def answers(vref, path, config, work):
    out = os.path.join(work, os.path.basename(path) + ".answers.jsonl")
    subprocess.run([vref, "eval", "--config", config, "--dataset", path, "--method", "rigid",
                    "--answers", out, "--json"], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    with open(out) as f:
        return [json.loads(line) for line in f]


def fit(rows, weights, iterations=60):
    xs = [features(r) for r in rows]
    ys = [1.0 if r["correct"] else 0.0 for r in rows]
    k = len(xs[0])
    w = [0.0, 1.0, 0.0, 0.0, 0.0]
    for _ in range(iterations):
        grad = [0.0] * k
        hess = [[1e-4 if i == j else 0.0 for j in range(k)] for i in range(k)]
        for x, y, v in zip(xs, ys, weights):
            z = sum(wi * xi for wi, xi in zip(w, x))
            p = 1 / (1 + math.exp(-max(min(z, 40), -40)))
            for i in range(k):
                grad[i] += v * (p - y) * x[i]
                for j in range(k):
                    hess[i][j] += v * p * (1 - p) * x[i] * x[j]
        step = solve(hess, grad)
        w = [wi - si for wi, si in zip(w, step)]
        if max(abs(s) for s in step) < 1e-9:
            break
    return w


def probability(w, row):
    z = sum(wi * xi for wi, xi in zip(w, features(row)))
    return 1 / (1 + math.exp(-max(min(z, 40), -40)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--settings", help="a file of further [matching.rigid] lines")
    parser.add_argument("--vref", default="target/release/vref")
    parser.add_argument("--positions", action="store_true",
                        help="fit the map for views without telling appearance")
    parser.add_argument("files", nargs="+")
    args = parser.parse_args()
    settings = open(args.settings).read() if args.settings else ""
    with tempfile.TemporaryDirectory() as work:
        config = os.path.join(work, "identity.toml")
        with open(config, "w") as f:
            f.write("[matching.rigid]\n" + settings + "\n[matching.rigid.calibration]\n"
                    "bias = 0.0\nslope = 1.0\nno_partner_shift = 0.0\n"
                    "partner_margin = 0.0\nnone_margin = 0.0\n")
        files = [without_features(p, work) for p in args.files] if args.positions else args.files
        with ThreadPoolExecutor(max_workers=2) as pool:
            per_file = list(pool.map(lambda p: answers(args.vref, p, config, work), files))
    rows, weights = [], []
    for file_rows in per_file:
        rows += file_rows
        weights += [1.0 / len(file_rows)] * len(file_rows)
    w = fit(rows, weights)
    print("[matching.rigid.calibration]")
    for name, value in zip(["bias", "slope", "no_partner_shift", "partner_margin",
                            "none_margin"], w):
        print(f"{name} = {value:.4f}")
    for path, file_rows in zip(args.files, per_file):
        pairs = [(probability(w, r), r["correct"]) for r in file_rows]
        print(f"# {os.path.basename(path)}: {len(file_rows)} answers, training ECE "
              f"{ece(pairs):.3f} (sampling floor {floor([p for p, _ in pairs]):.3f})",
              file=sys.stderr)


def floor(confidences, draws=200):
    """The mean ECE of answers right exactly as often as their confidence
    says, at these confidences: what a file of this size shows by chance."""
    rng = random.Random(1)
    return sum(ece([(c, rng.random() < c) for c in confidences])
               for _ in range(draws)) / draws


if __name__ == "__main__":
    main()
