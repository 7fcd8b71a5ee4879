#!/usr/bin/env python3
"""Prints docs/method.md's tables (markdown) from the JSON that
tools/method-tables.sh writes: per data set, every method's accuracy,
precision, recall, ECE and mean solve time, with rigid's margin over the
best other method; then the coincidence test.

    python3 tools/results-tables.py [docs/results]
"""
import json
import os
import sys

results = sys.argv[1] if len(sys.argv) > 1 else "docs/results"
for name in ["method-vrefsim.json", "method-external.json", "method-bop.json"]:
    path = os.path.join(results, name)
    if not os.path.exists(path):
        continue
    rows = [json.loads(line) for line in open(path)]
    print(f"\nFrom `{path}`:\n")
    print("| set | method | accuracy | precision | recall | ECE | mean solve |")
    print("|---|---|---|---|---|---|---|")
    for dataset in dict.fromkeys(r["dataset"] for r in rows):
        these = [r for r in rows if r["dataset"] == dataset]
        best_other = max(r["accuracy"] for r in these if r["method"] != "rigid")
        for r in these:
            label = os.path.basename(dataset).replace(".jsonl", "") if r is these[0] else ""
            bold = "**" if r["method"] == "rigid" else ""
            print(f"| {label} | {bold}{r['method']}{bold} | {r['accuracy']:.3f} | "
                  f"{r['precision']:.3f} | {r['recall']:.3f} | {r['ece']:.3f} | "
                  f"{r['mean_solve_us'] / 1000:.2f} ms |")
        rigid = next(r for r in these if r["method"] == "rigid")
        print(f"|  | rigid - best other | {rigid['accuracy'] - best_other:+.3f} | | | | |")
path = os.path.join(results, "coincidence.json")
if os.path.exists(path):
    rows = [json.loads(line) for line in open(path)]
    print(f"\nFrom `{path}`:\n")
    print("| unrelated views | answers | with a partner | ok (partner, confidence >= 0.5) |")
    print("|---|---|---|---|")
    for r in rows:
        print(f"| {r['dataset'].replace('.jsonl', '')} | {r['answers']} | {r['partners']} | "
              f"{r['ok']} ({100 * r['ok_share']:.1f}%) |")
    total = sum(r["answers"] for r in rows)
    ok = sum(r["ok"] for r in rows)
    print(f"| all | {total} | {sum(r['partners'] for r in rows)} | {ok} ({100 * ok / total:.1f}%) |")
