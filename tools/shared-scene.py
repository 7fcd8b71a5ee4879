"""The floor of telling shared scenes from unrelated views by rigid's
scene measures (see tools/shared-scene.sh, which makes the answers)."""

import collections
import glob
import json
import math
import sys

import numpy as np


def scenes(path):
    by_scene = collections.defaultdict(list)
    with open(path) as f:
        for line in f:
            r = json.loads(line)
            by_scene[r["scene"]].append(r)
    return list(by_scene.values())


def measures(rows):
    """significance, margin (clamped as the calibration does), settled,
    fit, share and log of the smaller view's size."""
    r = rows[0]
    margin = 3.0 if r["margin"] is None else max(-3.0, min(3.0, r["margin"]))
    settled = 1.0 if r["margin"] is None else 0.0
    sig = -4.0 if r["significance"] is None else max(-10.0, min(10.0, r["significance"]))
    smaller = max(1, min(r["human_objects"], r["robot_objects"]))
    share = sum(x["matched"] for x in rows) / smaller
    unseen = r.get("unseen")
    return [margin, settled, sig, r["fit"], share, math.log(smaller),
            0.0 if unseen is None else unseen]


def logistic(x, y, weights, l2=1e-3, rounds=50):
    xb = np.hstack([x, np.ones((len(x), 1))])
    b = np.zeros(xb.shape[1])
    for _ in range(rounds):
        p = 1 / (1 + np.exp(-xb @ b))
        g = xb.T @ (weights * (p - y)) / weights.sum() + l2 * b
        h = (xb * (weights * p * (1 - p))[:, None]).T @ xb / weights.sum() + l2 * np.eye(len(b))
        b -= np.linalg.solve(h, g)
    return b, 1 / (1 + np.exp(-xb @ b))


def ece(pairs, bins=10):
    v = np.array(pairs, dtype=float)
    total = 0.0
    for i in range(bins):
        hi = v[:, 0] < (i + 1) / bins if i < bins - 1 else np.ones(len(v), bool)
        s = (v[:, 0] >= i / bins) & hi
        if s.any():
            total += s.sum() / len(v) * abs(v[s, 0].mean() - v[s, 1].mean())
    return total


def main(work):
    x, y, files, rows = [], [], [], []
    for path in sorted(glob.glob(f"{work}/*.jsonl")):
        real = "/real-" in path
        for scene in scenes(path):
            x.append(measures(scene))
            y.append(1.0 if real else 0.0)
            files.append(path)
            rows.append(scene)
    x, y = np.array(x), np.array(y)
    weights = np.where(y == 1, 0.5 / y.sum(), 0.5 / (1 - y).sum())
    b, p = logistic(x, y, weights)
    print("scenes: real %d, unrelated %d" % (y.sum(), (1 - y).sum()))
    print("weights (margin, settled, significance, fit, share, ln size, unseen, bias):",
          " ".join("%.3f" % v for v in b))
    odds = p / (1 - p)
    print()
    print("| prior (views share a scene) | unrelated answers `ok` | largest ECE of a real training file | right partners `ok` on real files |")
    print("|---|---|---|---|")
    for prior in [None, 0.99, 0.95, 0.9, 0.8, 0.5]:
        by_file = collections.defaultdict(list)
        ok_null = total_null = right_ok = 0
        for k, scene in enumerate(rows):
            post = 1.0 if prior is None else odds[k] * prior / (odds[k] * prior + 1 - prior)
            for a in scene:
                if prior is None:
                    c, ok = a["confidence"], a["status"] == "ok"
                else:
                    c = a["confidence"] * post if a["matched"] else a["confidence"]
                    ok = a["matched"] and a["status"] != "no_match" and c >= 0.5
                by_file[files[k]].append((c, a["correct"]))
                if y[k] == 0:
                    total_null += 1
                    ok_null += ok
                elif ok and a["correct"] and a["matched"]:
                    right_ok += 1
        worst = max(ece(v) for f, v in by_file.items() if "/real-" in f)
        label = "as today (none)" if prior is None else "%.2f" % prior
        print("| %s | %d of %d (%.1f%%) | %.3f | %d |"
              % (label, ok_null, total_null, 100 * ok_null / total_null, worst, right_ok))
    unseen_table(rows, y)


def unseen_table(rows, y):
    """What a hard rule on the unseen share alone would take: `ok`
    answers of scenes above each threshold, real (right ones) and
    unrelated."""
    print()
    print("| unseen share above | real `ok` answers above it (right) | unrelated `ok` answers above it |")
    print("|---|---|---|")
    null_ok = sum(a["status"] == "ok" for k, sc in enumerate(rows) if y[k] == 0 for a in sc)
    for t in [0.15, 0.2, 0.25, 0.3, 0.4]:
        real_ok = right = unrelated = 0
        for k, scene in enumerate(rows):
            u = scene[0].get("unseen")
            if u is None or u <= t:
                continue
            ok = [a for a in scene if a["status"] == "ok"]
            if y[k] == 1:
                real_ok += len(ok)
                right += sum(a["correct"] for a in ok)
            else:
                unrelated += len(ok)
        print("| %.2f | %d (%d) | %d of %d |" % (t, real_ok, right, unrelated, null_ok))


if __name__ == "__main__":
    main(sys.argv[1])
