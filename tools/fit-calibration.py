#!/usr/bin/env python3
"""Fits the `rigid` method's confidence calibration on training seeds.

    python3 tools/fit-calibration.py [--seeds 100-109] [--vref target/release/vref]

For each preset (moi, mrc) and each training seed it generates 30 scenes,
runs `vref eval --method rigid --answers` with the calibration switched to
the identity (bias 0, slope 1, no_partner_shift 0), so that every
answer's confidence is its raw share (abstention, decided on raw shares,
stays as configured), then fits the logistic
map `p = sigmoid(bias + slope * logit(raw) + no_partner_shift * [no
partner])` by Newton's method on the log loss. It prints the
`[matching.rigid.calibration]` constants, which go into
crates/vref-match/src/calibration.rs (the defaults) and config/vref.toml.
Only training seeds are used: the README's figures come from other seeds.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

EPS = 1e-6


def logit(p):
    p = min(max(p, EPS), 1 - EPS)
    return math.log(p / (1 - p))


def answers(vref, preset, seed, work):
    scenes = os.path.join(work, f"{preset}-{seed}.jsonl")
    out = os.path.join(work, f"{preset}-{seed}.answers.jsonl")
    config = os.path.join(work, "identity.toml")
    with open(config, "w") as f:
        f.write("[matching.rigid.calibration]\nbias = 0.0\nslope = 1.0\nno_partner_shift = 0.0\n")
    subprocess.run([vref, "scenes", "--preset", preset, "--count", "30", "--seed", str(seed),
                    "--out", scenes], check=True, stderr=subprocess.DEVNULL)
    subprocess.run([vref, "eval", "--config", config, "--dataset", scenes, "--method", "rigid",
                    "--answers", out, "--json"], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    with open(out) as f:
        return [json.loads(line) for line in f]


def fit(rows, iterations=50):
    """Logistic regression of `correct` on (1, logit(raw), no partner)."""
    xs = [(1.0, logit(r["confidence"]), 0.0 if r["matched"] else 1.0) for r in rows]
    ys = [1.0 if r["correct"] else 0.0 for r in rows]
    w = [0.0, 1.0, 0.0]
    for _ in range(iterations):
        grad = [0.0] * 3
        hess = [[1e-6 if i == j else 0.0 for j in range(3)] for i in range(3)]
        for x, y in zip(xs, ys):
            z = sum(wi * xi for wi, xi in zip(w, x))
            p = 1 / (1 + math.exp(-max(min(z, 40), -40)))
            for i in range(3):
                grad[i] += (p - y) * x[i]
                for j in range(3):
                    hess[i][j] += p * (1 - p) * x[i] * x[j]
        step = solve3(hess, grad)
        w = [wi - si for wi, si in zip(w, step)]
        if max(abs(s) for s in step) < 1e-10:
            break
    return w


def solve3(a, b):
    """Gaussian elimination for a 3x3 system."""
    m = [row[:] + [v] for row, v in zip(a, b)]
    for c in range(3):
        pivot = max(range(c, 3), key=lambda r: abs(m[r][c]))
        m[c], m[pivot] = m[pivot], m[c]
        for r in range(3):
            if r != c and m[c][c] != 0:
                f = m[r][c] / m[c][c]
                m[r] = [x - f * y for x, y in zip(m[r], m[c])]
    return [m[i][3] / m[i][i] if m[i][i] != 0 else 0.0 for i in range(3)]


def ece(pairs, bins=10):
    counts = [[0, 0.0, 0] for _ in range(bins)]
    for c, ok in pairs:
        b = min(int(c * bins), bins - 1)
        counts[b][0] += 1
        counts[b][1] += c
        counts[b][2] += ok
    n = len(pairs)
    return sum(k / n * abs(s / k - r / k) for k, s, r in counts if k)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", default="100-109", help="training seeds, FIRST-LAST")
    parser.add_argument("--vref", default="target/release/vref")
    args = parser.parse_args()
    first, last = (int(s) for s in args.seeds.split("-"))
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for preset in ("moi", "mrc"):
            for seed in range(first, last + 1):
                rows += answers(args.vref, preset, seed, work)
    bias, slope, shift = fit(rows)
    def calibrated(r):
        z = bias + slope * logit(r["confidence"]) + (0.0 if r["matched"] else shift)
        return 1 / (1 + math.exp(-z))
    raw_ece = ece([(r["confidence"], r["correct"]) for r in rows])
    fit_ece = ece([(calibrated(r), r["correct"]) for r in rows])
    print(f"# {len(rows)} answers from seeds {first}-{last} of moi and mrc; "
          f"ECE raw {raw_ece:.4f}, calibrated {fit_ece:.4f} (training set)")
    print("[matching.rigid.calibration]")
    print(f"bias = {bias:.4f}")
    print(f"slope = {slope:.4f}")
    print(f"no_partner_shift = {shift:.4f}")


if __name__ == "__main__":
    sys.exit(main())
