#!/usr/bin/env python3
"""Times pygmtools' RRWM and SM on vref dataset files, for comparison with
`vref bench solver` (same scenes) and `vref eval` (same answers). Not part
of CI.

The scenes: `vref scenes --preset rigid --objects N --count 8 --seed 1` writes exactly the
eight scenes of N objects per view that `vref bench solver` times by
default (seed 1), with their ground truth; any other dataset file works too
(scenes are grouped by their human object count).

The affinity is the one vref's methods use (ALGORITHMS.md): edge affinity
exp(-(d - d')^2 / beta) between edge lengths, every ordered pair of objects
unless a view lists "edges"; node affinity 0 (vref's sm and rrwm ignore
appearance) or, with --node cosine, the cosine of the features as vref's
appearance term. The solvers get ALGORITHMS.md's constants where pygmtools
has them: RRWM c = alpha = 0.2, jump amplification beta = 30, at most 300
iterations; SM at most 1000 iterations. pygmtools keeps its own stopping
rules (change below 1e-5) and runs a fixed 20 Sinkhorn rounds inside RRWM
(vref: row and column sums within 1e-3, up to 1000 rounds), so iteration
counts differ; the answers are compared through accuracy against the
file's ground truth. pygmtools runs on its numpy backend on one thread.

Usage (pip install pygmtools==0.6.0; numpy backend, no torch needed):

    python3 tools/pygmtools_bench.py --dataset FILE.jsonl [FILE2.jsonl ...]
        [--beta 0.01] [--method rrwm --method sm] [--repeats 5]
        [--node zero|cosine] [--params algorithms|defaults] [--json]

For each method and scene size (human objects per scene) it prints the
median and p99 over scenes and repeats of building the (nn')^2 affinity
matrix (pygm.utils.build_aff_mat), of the solve (pygm.rrwm / pygm.sm plus
pygm.hungarian), and of both together (what `vref bench solver` times as
a full solve), plus the accuracy against the file's ground truth and the
number of scenes answered perfectly. With --json: one object per line,
{"method", "params", "objects", "scenes", "affinity_median_us", "affinity_p99_us",
"solve_median_us", "solve_p99_us", "total_median_us", "total_p99_us",
"accuracy", "perfect_scenes"}.
"""

import os

# One thread, set before numpy is imported.
for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
            "NUMEXPR_NUM_THREADS", "VECLIB_MAXIMUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections import defaultdict  # noqa: E402

import numpy as np  # noqa: E402
import pygmtools as pygm  # noqa: E402

pygm.set_backend("numpy")


def view(graph):
    """Positions, features and directed edges (both directions) of a view."""
    objects = graph["objects"]
    ids = [o["id"] for o in objects]
    pos = np.array([o["position"] for o in objects], dtype=np.float64)
    feats = [o.get("feature") or [] for o in objects]
    dim = len(feats[0]) if feats else 0
    feat = np.array(feats, dtype=np.float64).reshape(len(objects), dim)
    index = {k: i for i, k in enumerate(ids)}
    if graph.get("edges"):
        pairs = [(index[a], index[b]) for a, b in graph["edges"] if a != b]
        pairs = sorted({(min(p), max(p)) for p in pairs})
    else:
        n = len(objects)
        pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]
    directed = pairs + [(j, i) for i, j in pairs]
    conn = np.array(directed, dtype=np.int64).reshape(-1, 2)
    length = np.linalg.norm(pos[conn[:, 0]] - pos[conn[:, 1]], axis=1)
    return ids, feat, conn, length[:, None]


def cosine(f1, f2):
    """vref's appearance: cosine, 1 where a side has no feature or norm 0."""
    if f1.shape[-1] == 0 or f2.shape[-1] == 0:
        return np.ones((f1.shape[0], f2.shape[0]))
    n1 = np.linalg.norm(f1, axis=1)[:, None]
    n2 = np.linalg.norm(f2, axis=1)[None, :]
    dots = f1 @ f2.T
    with np.errstate(invalid="ignore", divide="ignore"):
        a = dots / (n1 * n2)
    return np.where((n1 == 0) | (n2 == 0), 1.0, a)


def affinity(human, robot, beta, node):
    _, hf, hc, hl = human
    _, rf, rc, rl = robot
    n1, n2 = hf.shape[0], rf.shape[0]

    def edge_aff(e1, e2):
        # (b, ne1, 1) x (b, ne2, 1) -> (b, ne1, ne2)
        d = e1[:, :, None, 0] - e2[:, None, :, 0]
        return np.exp(-(d * d) / beta)

    def node_aff(f1, f2):
        if node == "zero":
            return np.zeros((f1.shape[0], f1.shape[1], f2.shape[1]))
        return cosine(f1[0], f2[0])[None]

    # Node "features" only carry what node_aff needs; pad an empty feature.
    hfe = hf if hf.shape[1] else np.zeros((n1, 1))
    rfe = rf if rf.shape[1] else np.zeros((n2, 1))
    return pygm.utils.build_aff_mat(
        hfe[None], hl[None], hc[None], rfe[None], rl[None], rc[None],
        np.array([n1]), np.array([hc.shape[0]]), np.array([n2]), np.array([rc.shape[0]]),
        node_aff_fn=node_aff, edge_aff_fn=edge_aff,
    )


def percentile(values, q):
    """Nearest rank, vref's one definition (vref_measure::percentile,
    vref_client.measure.percentile): the value at rank ceil(q*n), 1-based,
    a product within 1e-9 of a whole number counting as that number."""
    s = sorted(values)
    x = q * len(s)
    if abs(x - round(x)) < 1e-9:
        x = round(x)
    return s[min(max(math.ceil(x), 1), len(s)) - 1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dataset", nargs="+", required=True)
    parser.add_argument("--beta", type=float, default=0.01)
    parser.add_argument("--method", action="append", choices=["rrwm", "sm"])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--node", choices=["zero", "cosine"], default="zero")
    parser.add_argument("--params", choices=["algorithms", "defaults"], default="algorithms",
                        help="ALGORITHMS.md's constants (default) or pygmtools' own "
                             "(RRWM: at most 50 iterations; SM: at most 50)")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    methods = args.method or ["rrwm", "sm"]
    # ALGORITHMS.md's constants, where pygmtools has a parameter for them.
    solvers = {
        "rrwm": lambda K, n1, n2: pygm.rrwm(K, n1, n2, max_iter=300, alpha=0.2, beta=30),
        "sm": lambda K, n1, n2: pygm.sm(K, n1, n2, max_iter=1000),
    }
    if args.params == "defaults":
        solvers = {"rrwm": pygm.rrwm, "sm": pygm.sm}

    pairs = []
    for path in args.dataset:
        with open(path) as f:
            pairs += [json.loads(line) for line in f if line.strip()]

    solve_us = defaultdict(list)
    aff_us = defaultdict(list)
    total_us = defaultdict(list)
    perfect = defaultdict(int)
    right = defaultdict(lambda: [0, 0])
    scenes = defaultdict(set)
    for p in pairs:
        human, robot = view(p["human"]), view(p["robot"])
        n1, n2 = len(human[0]), len(robot[0])
        truth = {h: r for h, r in p.get("ground_truth", [])}
        for method in methods:
            key = (method, n1)
            scenes[key].add(p.get("name"))
            for _ in range(args.repeats):
                t0 = time.perf_counter()
                K = affinity(human, robot, args.beta, args.node)
                t1 = time.perf_counter()
                soft = solvers[method](K, np.array([n1]), np.array([n2]))
                X = pygm.hungarian(soft)
                t2 = time.perf_counter()
                aff_us[key].append((t1 - t0) * 1e6)
                solve_us[key].append((t2 - t1) * 1e6)
                total_us[key].append((t2 - t0) * 1e6)
            X = X[0]
            wrong = 0
            for i, h in enumerate(human[0]):
                cols = np.nonzero(X[i])[0]
                pred = robot[0][cols[0]] if len(cols) else None
                ok = pred == truth.get(h)
                right[key][0] += ok
                right[key][1] += 1
                wrong += not ok
            perfect[key] += wrong == 0

    if not args.json:
        print(f"pygmtools {pygm.__version__}, numpy backend, 1 thread, {args.repeats} repeats per scene")
        print(f"{'method':<6} {'objects':>7} {'scenes':>6} {'affinity med us':>15} "
              f"{'solve med us':>12} {'solve p99 us':>12} {'total med us':>12} {'total p99 us':>12} "
              f"{'accuracy':>8} {'perfect':>7}")
    for key in sorted(solve_us):
        method, n = key
        row = {
            "method": method,
            "params": args.params,
            "objects": n,
            "scenes": len(scenes[key]),
            "solve_median_us": percentile(solve_us[key], 0.5),
            "solve_p99_us": percentile(solve_us[key], 0.99),
            "affinity_median_us": percentile(aff_us[key], 0.5),
            "affinity_p99_us": percentile(aff_us[key], 0.99),
            "total_median_us": percentile(total_us[key], 0.5),
            "total_p99_us": percentile(total_us[key], 0.99),
            "accuracy": right[key][0] / max(1, right[key][1]),
            "perfect_scenes": perfect[key],
        }
        if args.json:
            print(json.dumps(row))
        else:
            print(f"{method:<6} {n:>7} {row['scenes']:>6} {row['affinity_median_us']:>15.0f} "
                  f"{row['solve_median_us']:>12.0f} {row['solve_p99_us']:>12.0f} "
                  f"{row['total_median_us']:>12.0f} {row['total_p99_us']:>12.0f} "
                  f"{row['accuracy']:>8.3f} {row['perfect_scenes']:>7}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
