#!/usr/bin/env python3
"""How the coincidence rule of `rigid` was chosen (docs/method.md,
"Coincidence"). Reads answer files written with the rule off:

    cargo run --release -p vref-research --example rigid_answers -- \\
        --no-gate --per-seed DIR

(real training sets as NAME.jsonl, one per sim seed; unrelated views as
null-*.jsonl). A motion is taken as chance when its evidence,
significance + a x margin + b x share + f x fit (share: partners given
over the smaller view's size; fit: the motion's score under the assumed
noise over the largest possible; a significance not measured counts -4, a
settled scene's margin is infinite), is below c; its partners' confidence
is then capped at CAP (0.45). For every (a, b, f, c) of a grid it computes every real
training file's ECE and the share of `ok` answers (a partner at confidence
0.5 or more) among the unrelated views made as the reporting ones are (the
first seed of each sim preset, the external and BOP training halves, the
clouds), and prints the rules with the fewest `ok` answers among those that
raise no real training file's ECE by more than MAX_RISE (0.005) and keep
each at most MAX_ECE (default 1: not a constraint). A budget of MAX_ECE =
0.045 instead of the rise was tried and did not carry over to the
reporting files (docs/method.md, "Coincidence").

    python3 tools/coincidence-gate.py DIR
"""
import collections
import glob
import itertools
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ece import ece  # noqa: E402

CAP = float(os.environ.get("CAP", "0.45"))
MAX_ECE = float(os.environ.get("MAX_ECE", "1"))
MAX_RISE = float(os.environ.get("MAX_RISE", "0.005"))
UNMEASURED = -4.0


def scenes(path):
    by_scene = collections.OrderedDict()
    for line in open(path):
        a = json.loads(line)
        by_scene.setdefault(a["scene"], []).append(a)
    out = []
    for rows in by_scene.values():
        r = rows[0]
        share = sum(x["matched"] for x in rows) / max(1, min(r["human_objects"], r["robot_objects"]))
        sig = UNMEASURED if r["significance"] is None else r["significance"]
        margin = math.inf if r["margin"] is None else r["margin"]
        fit = r.get("fit") or 0.0
        out.append((sig, margin, share, fit, [(x["confidence"], x["correct"], x["matched"]) for x in rows]))
    return out


def evidence(scene, a, b, f):
    sig, margin, share, fit, _ = scene
    if margin == math.inf:  # a settled scene is never chance
        return math.inf
    return sig + a * margin + b * share + f * fit


def capped_ece(scene_list, fires):
    """ECE of the answers with the partners of each scene that `fires`
    capped at CAP."""
    return ece(
        (min(c, CAP) if fire and matched else c, ok)
        for (*_, rows), fire in zip(scene_list, fires)
        for c, ok, matched in rows
    )


def reported_like(name):
    # One sim seed's unrelated views per preset, as the reporting views have.
    sim = name.startswith(("null-Moi", "null-Mrc"))
    return not sim or name.startswith(("null-Moi100", "null-Mrc100"))


def describe(real, null):
    """Each measure's 5th, 50th and 95th percentile among the real scenes
    no decisive motion settled and among the unrelated views with an `ok`
    answer (rule off)."""
    groups = {
        "real, unsettled": [s for v in real.values() for s in v if s[1] != math.inf],
        "unrelated, with an ok answer": [
            s for v in null.values() for s in v
            if s[1] != math.inf and any(m and c >= 0.5 for c, _, m in s[-1])
        ],
    }
    for name, group in groups.items():
        cells = []
        for k, measure in enumerate(["significance", "margin", "share", "fit"]):
            values = sorted(s[k] for s in group)
            if values:
                at = [values[int(p * (len(values) - 1))] for p in (0.05, 0.5, 0.95)]
                cells.append(f"{measure} {at[1]:.2f} ({at[0]:.2f} to {at[2]:.2f})")
        print(f"{name} ({len(group)} scenes): " + ", ".join(cells))


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: python3 tools/coincidence-gate.py DIR (answer files written with the rule off)")
    d = sys.argv[1]
    real, null = {}, {}
    for path in sorted(glob.glob(d + "/*.jsonl")):
        name = os.path.basename(path)[: -len(".jsonl")]
        if not name.startswith("null-"):
            real[name] = scenes(path)
        elif reported_like(name):
            null[name] = scenes(path)
    if not real or not null:
        sys.exit(f"coincidence-gate.py: no answer files in {d}")
    answers = sum(len(s[-1]) for v in null.values() for s in v)
    base = {k: capped_ece(v, [False] * len(v)) for k, v in real.items()}
    results = []
    for a, b, f in itertools.product([0, 1, 2, 4], [0, 1, 2, 3, 4, 6, 8, 12], [0, 4, 6, 8, 12, 16]):
        for c in [x / 4 for x in range(-24, 80)]:
            eces = {k: capped_ece(v, [evidence(s, a, b, f) < c for s in v]) for k, v in real.items()}
            worst = max((e, k) for k, e in eces.items())
            rise = max(e - base[k] for k, e in eces.items())
            if worst[0] > MAX_ECE or rise > MAX_RISE:
                continue
            ok = sum(
                1
                for v in null.values()
                for s in v
                if not evidence(s, a, b, f) < c
                for conf, _, matched in s[-1]
                if matched and conf >= 0.5
            )
            results.append((ok / answers, a, b, f, c, worst, rise))
    describe(real, null)
    off = sum(1 for v in null.values() for s in v for conf, _, m in s[-1] if m and conf >= 0.5)
    print(f"rule off: {100 * off / answers:.2f}% of {answers} unrelated answers ok")
    for share, a, b, f, c, (worst, name), rise in sorted(results)[:10]:
        print(
            f"a {a} b {b} f {f} c {c}: ok {100 * share:.2f}%, largest ECE {worst:.4f} ({name}),"
            f" largest rise {rise:.4f}"
        )


if __name__ == "__main__":
    main()
