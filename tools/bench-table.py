#!/usr/bin/env python3
"""Markdown table of `vref bench solver --json` lines read from stdin:
one row per tier and mode, one column per size, "median (p99), iterations"."""
import json
import sys

rows, sizes = {}, set()
for line in sys.stdin:
    d = json.loads(line)
    rows.setdefault((d["method"], d["tier"], d["mode"]), {})[d["objects"]] = d
    sizes.add(d["objects"])
sizes = sorted(sizes)


def ms(us):
    return f"{us / 1000:.1f} ms" if us >= 1000 else f"{us:.0f} us"


print("| method | tier | mode | " + " | ".join(str(s) for s in sizes) + " |")
print("|---|---|---|" + "---|" * len(sizes))
for (method, tier, mode), by_size in rows.items():
    cells = [
        f"{ms(by_size[s]['median_us'])} ({ms(by_size[s]['p99_us'])}), {by_size[s]['iterations']} it"
        if s in by_size else "not run"
        for s in sizes
    ]
    print(f"| {method} | {tier} | {mode} | " + " | ".join(cells) + " |")
