"""How far a calibration could take answers given without appearance
(docs/method.md, "Without appearance: not calibrated"): for each answers
file of `vref eval --answers` on a training file with its features
removed, ECE as given, after logistic maps fitted in-sample on all the
files together (the confidence's logit and "no partner" alone; with the
scene's sizes; with its search settled, significance and fit too), and
the file's sampling floor (the mean ECE of answers exactly as right as
their confidences say, 200 seeded draws). A map fitted on the very answers
it is scored on is an upper bound on what any calibration could do.

    bash tools/without-features.sh ANSWERS_DIR   # writes ANSWERS_DIR/FILE.jsonl
    python3 tools/featureless-recalibration.py ANSWERS_DIR/*.jsonl
"""

import json
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(__file__))
from ece import ece  # noqa: E402
from linear import solve  # noqa: E402


def measures(r):
    c = min(max(r["confidence"], 1e-6), 1 - 1e-6)
    logit = math.log(c / (1 - c))
    none = float(r["partner"] is None)
    significance = r["significance"] if r["significance"] is not None else -4.0
    return [1.0, logit, none, logit * none,
            math.log(r["human_objects"]), math.log(r["robot_objects"]),
            float(r["margin"] is None), significance / 4, r["fit"]]


MAPS = [("refitted", 4), ("with sizes", 6), ("with sizes, settled, significance, fit", 9)]


def fit(xs, ys, k, rounds=40):
    """Logistic regression on the first `k` measures by Newton's method,
    with a tiny ridge so that a measure constant over the answers is no
    singularity."""
    w = [0.0] * k
    for _ in range(rounds):
        grad = [0.0] * k
        hess = [[1e-6 if i == j else 0.0 for j in range(k)] for i in range(k)]
        for x, y in zip(xs, ys):
            z = sum(wi * xi for wi, xi in zip(w, x[:k]))
            p = 1 / (1 + math.exp(-max(min(z, 700), -700)))
            for i in range(k):
                grad[i] += (p - y) * x[i]
                for j in range(k):
                    hess[i][j] += p * (1 - p) * x[i] * x[j]
        step = solve(hess, grad)
        w = [wi - si for wi, si in zip(w, step)]
    return w


def sampling_floor(confidences, draws=200):
    rng = random.Random(1)
    return sum(ece([(c, rng.random() < c) for c in confidences])
               for _ in range(draws)) / draws


def main():
    files = sys.argv[1:]
    rows = {f: [json.loads(line) for line in open(f)] for f in files}
    xs = [measures(r) for f in files for r in rows[f]]
    ys = [float(r["correct"]) for f in files for r in rows[f]]
    weights = [fit(xs, ys, k) for _, k in MAPS]
    print("| answers | ECE as given | " + " | ".join(name for name, _ in MAPS)
          + " | sampling floor |")
    print("|---|---|" + "---|" * len(MAPS) + "---|")
    for f in files:
        given = [(r["confidence"], r["correct"]) for r in rows[f]]
        cells = ["%.3f" % ece(given)]
        for (_, k), w in zip(MAPS, weights):
            mapped = []
            for r in rows[f]:
                z = sum(wi * xi for wi, xi in zip(w, measures(r)[:k]))
                mapped.append((1 / (1 + math.exp(-max(min(z, 700), -700))), r["correct"]))
            cells.append("%.3f" % ece(mapped))
        cells.append("%.3f" % sampling_floor([r["confidence"] for r in rows[f]]))
        name = os.path.basename(f).removesuffix(".jsonl")
        print("| %s | %s |" % (name, " | ".join(cells)))


if __name__ == "__main__":
    main()
