#!/usr/bin/env python3
"""Rewrites the marked tables of markdown files from docs/results/.

A table is a block

    <!-- table: KIND FILE [ARG] -->
    ...whatever was there...
    <!-- /table -->

and its contents are replaced by the table KIND makes from FILE (a path
from the repository root), headed by the file's name and the run that
wrote it (docs/results/run.json). A file or row that is missing gives a
visible "not measured" line, never an old figure.

    python3 tools/tables.py README.md docs/*.md     # rewrite in place
    python3 tools/tables.py --check README.md ...   # exit 1 if any would change
"""
import json
import os
import re
import sys

BLOCK = re.compile(r"(<!-- table: (?P<spec>[^>]*?) -->\n)(?P<body>.*?)(<!-- /table -->)", re.S)
FAMILIES = {"moi": "vref-sim moi (table top)", "mrc": "vref-sim mrc (floor)",
            "moi-ext-report": "external moi-ext", "mrc-ext-report": "external mrc-ext",
            "bop-table-report": "rendered BOP table", "bop-floor-report": "rendered BOP floor"}


def lines(path):
    """A file of one JSON value (a list is its rows) or of JSON lines."""
    with open(path) as f:
        text = f.read().strip()
    try:
        value = json.loads(text)
    except json.JSONDecodeError:
        return [json.loads(l) for l in text.splitlines() if l.strip()]
    return value if isinstance(value, list) else [value]


def run_note():
    path = "docs/results/run.json"
    if not os.path.exists(path):
        return ""
    r = lines(path)[0]
    return f", {r['mode']} run, {r['date']}, {r['commit']}, {r['cores']} cores at load {r['load_at_start']}"


def name(dataset):
    return os.path.basename(dataset).replace(".jsonl", "")


def ms(us):
    if us is None:
        return "-"
    if us >= 1e6:
        return f"{us / 1e6:.2f} s"
    return f"{us / 1000:.2f} ms" if us >= 1000 else f"{us:.0f} us"


def method_table(rows, _arg):
    out = ["| set | method | accuracy | precision | recall | ECE | mean solve |",
           "|---|---|---|---|---|---|---|"]
    for dataset in dict.fromkeys(r["dataset"] for r in rows):
        these = [r for r in rows if r["dataset"] == dataset]
        for i, r in enumerate(these):
            bold = "**" if r["method"] == "rigid" else ""
            out.append(f"| {name(dataset) if i == 0 else ''} | {bold}{r['method']}{bold} | "
                       f"{r['accuracy']:.3f} | {r['precision']:.3f} | {r['recall']:.3f} | "
                       f"{r['ece']:.3f} | {r['mean_solve_us'] / 1000:.2f} ms |")
        rigid = [r for r in these if r["method"] == "rigid"]
        others = [r["accuracy"] for r in these if r["method"] != "rigid"]
        if rigid and others:
            out.append(f"|  | rigid - best other | {rigid[0]['accuracy'] - max(others):+.3f} | | | | |")
    return out


def coincidence_table(rows, _arg):
    out = ["| unrelated views | answers | with a partner | ok (partner, confidence >= 0.5) |",
           "|---|---|---|---|"]
    total = [0, 0, 0]
    for r in sorted(rows, key=lambda r: r["dataset"]):
        out.append(f"| {name(r['dataset'])} | {r['answers']} | {r['partners']} | "
                   f"{r['ok']} ({100 * r['ok_share']:.1f}%) |")
        total = [total[0] + r["answers"], total[1] + r["partners"], total[2] + r["ok"]]
    out.append(f"| all | {total[0]} | {total[1]} | {total[2]} ({100 * total[2] / max(1, total[0]):.1f}%) |")
    return out


def family_groups():
    """The held-out method results grouped by family: {(family, file): {method: [rows]}}."""
    rows = []
    for file in ["method-vrefsim.json", "method-external.json", "method-bop.json"]:
        path = os.path.join("docs/results", file)
        if os.path.exists(path):
            rows += [dict(r, file=file) for r in lines(path)]
    groups = {}
    for r in rows:
        key = re.sub(r"\d+$", "", name(r["dataset"]))
        groups.setdefault((key, r["file"]), {}).setdefault(r["method"], []).append(r)
    return groups


def mean(rows, field):
    """Scene-weighted mean of `field` over a family's sets."""
    return sum(r[field] * r["scenes"] for r in rows) / sum(r["scenes"] for r in rows)


def family_label(key, sets):
    return FAMILIES.get(key, key) + (f", {sets} sets" if sets > 1 else "")


def accuracy_table(_rows, _arg):
    """The README's headline: rigid against the best other method, per family."""
    out = ["| held-out set | scenes | `rigid` accuracy / precision / ECE | best other method | file |",
           "|---|---|---|---|---|"]
    for (key, file), by_method in family_groups().items():
        if "rigid" not in by_method:
            continue
        best = max((m for m in by_method if m != "rigid"), key=lambda m: mean(by_method[m], "accuracy"))
        rigid = by_method["rigid"]
        scenes = sum(r["scenes"] for r in rigid)
        out.append(f"| {family_label(key, len(rigid))} | {scenes} | {mean(rigid, 'accuracy'):.3f} / "
                   f"{mean(rigid, 'precision'):.3f} / {mean(rigid, 'ece'):.3f} | "
                   f"{best} {mean(by_method[best], 'accuracy'):.3f} | `docs/results/{file}` |")
    return out


def targets_table(_rows, _arg):
    """Per held-out set: rigid against issue 15's targets (accuracy >= 0.93,
    precision >= 0.95, ECE <= 0.05, accuracy >= best other + 0.03)."""
    out = ["| held-out set | `rigid` accuracy / precision / ECE | best other (accuracy) | `rigid` - best other | targets missed |",
           "|---|---|---|---|---|"]
    for file in ["method-vrefsim.json", "method-external.json", "method-bop.json"]:
        path = os.path.join("docs/results", file)
        if not os.path.exists(path):
            out.append(f"| `{file}` not measured | | | | |")
            continue
        rows = lines(path)
        for dataset in dict.fromkeys(r["dataset"] for r in rows):
            these = [r for r in rows if r["dataset"] == dataset]
            rigid = [r for r in these if r["method"] == "rigid"]
            others = [r for r in these if r["method"] != "rigid"]
            if not rigid or not others:
                continue
            r = rigid[0]
            best = max(others, key=lambda o: o["accuracy"])
            gap = r["accuracy"] - best["accuracy"]
            missed = [t for t, ok in [("accuracy", r["accuracy"] >= 0.93), ("precision", r["precision"] >= 0.95),
                                      ("ECE", r["ece"] <= 0.05), ("margin", gap >= 0.03)] if not ok]
            out.append(f"| {name(dataset)} | {r['accuracy']:.3f} / {r['precision']:.3f} / {r['ece']:.3f} | "
                       f"{best['method']} ({best['accuracy']:.3f}) | {gap:+.3f} | {', '.join(missed) or 'none'} |")
    return out


METHODS = ["appearance", "sm", "rrwm", "paper", "clipper", "rigid"]


def families_table(_rows, _arg):
    """Every method's accuracy per family of held-out sets; the best in bold."""
    out = ["| held-out set | " + " | ".join(f"`{m}`" for m in METHODS) + " |",
           "|---|" + "---|" * len(METHODS)]
    for (key, _file), by_method in family_groups().items():
        cells = {m: mean(by_method[m], "accuracy") for m in METHODS if m in by_method}
        if not cells:
            continue
        best = max(cells.values())
        sets = max(len(v) for v in by_method.values())
        row = [f"**{cells[m]:.3f}**" if m in cells and cells[m] == best
               else (f"{cells[m]:.3f}" if m in cells else "-") for m in METHODS]
        out.append(f"| {family_label(key, sets)} | " + " | ".join(row) + " |")
    return out


def cmu_table(rows, _arg):
    gaps = sorted({r["gap"] for r in rows})
    out = ["| method | " + " | ".join(f"gap {g}" for g in gaps) + " |", "|---|" + "---|" * len(gaps)]
    for method in dict.fromkeys(r["method"] for r in rows):
        cells = {r["gap"]: r["accuracy"] for r in rows if r["method"] == method}
        out.append(f"| {method} | " + " | ".join(f"{cells[g]:.3f}" if g in cells else "-" for g in gaps) + " |")
    return out


def solver_table(rows, _arg):
    sizes = sorted({r["objects"] for r in rows})
    out = ["| method | tier | mode | " + " | ".join(str(s) for s in sizes) + " |",
           "|---|---|---|" + "---|" * len(sizes)]
    table = {}
    for r in rows:
        table.setdefault((r["method"], r["tier"], r["mode"]), {})[r["objects"]] = r
    for (method, tier, mode), by_size in table.items():
        cells = [f"{ms(by_size[s]['median_us'])} ({ms(by_size[s]['p99_us'])})" if s in by_size else "not run"
                 for s in sizes]
        out.append(f"| {method} | {tier} | {mode} | " + " | ".join(cells) + " |")
    return out


def percentiles(r, prefixes):
    out = ["| round trip | count | p50 | p99 | p99.9 |", "|---|---|---|---|---|"]
    for prefix, label in prefixes:
        if f"{prefix}_p50_us" not in r:
            continue
        count = r.get(f"{prefix}_count", "")
        p999 = r.get(f"{prefix}_p999_us")
        out.append(f"| {label} | {count} | {ms(r[prefix + '_p50_us'])} | {ms(r[prefix + '_p99_us'])} | "
                   f"{ms(p999) if p999 is not None else '-'} |")
    return out


def query_table(rows, arg):
    """ARG `short`: only every answer against the bare echo."""
    r = rows[0]
    kinds = [("cached", "matcher, answer from the current solution"),
             ("solve", "matcher, first answer from a new solution"),
             ("all", "matcher, every answer"), ("bare", "bare iceoryx2 echo server")]
    out = percentiles(r, kinds[2:] if arg == "short" else kinds)
    if "idle_all_p99_us" in r and arg != "short":
        out.append(f"| idle matcher (feeds unheard), every answer | | {ms(r['idle_all_p50_us'])} | "
                   f"{ms(r['idle_all_p99_us'])} | - |")
        out.append(f"| idle phase, bare iceoryx2 echo server | | - | {ms(r['idle_bare_p99_us'])} | - |")
    if "solve_time_p50_us" in r and arg != "short":
        out.append(f"| (the matcher's solves, beside the queries) | {r.get('solve_time_count', '')} | "
                   f"{ms(r['solve_time_p50_us'])} | {ms(r['solve_time_p99_us'])} | - |")
    out.append("")
    out.append(f"{r['objects']} objects, method `{r['method']}`, tier `{r['tier']}`, {r['rate_hz']:.0f} ticks/s "
               f"for {r['duration_s']:.0f} s; `ratio_all_p99` (matcher / echo) {r['ratio_all_p99']:.2f}"
               + (f"; `ratio_busy_idle_p99` {r['ratio_busy_idle_p99']:.2f}" if "ratio_busy_idle_p99" in r else "")
               + f"; timeouts {r['timeouts']}, errors {r['errors']}.")
    return out


def demo_table(rows, _arg):
    r = rows[0]
    statuses = ", ".join(f"{k} {v}" for k, v in sorted(r.get("statuses", {}).items()) if v)
    # Wrong answers split by cause where the summary has it: the ray took
    # a neighbour of the object meant (pointing), or the matcher erred.
    split = "wrong_pointing" in r
    head = "| queries | answered | correct | accuracy |"
    head += " wrong: ray took a neighbour | wrong: about the object meant |" if split else ""
    row = f"| {r['queries']} | {r['answered']} | {r['correct']} | {r['accuracy']:.2f} |"
    row += f" {r['wrong_pointing']} | {r['wrong_matching']} |" if split else ""
    return [head + " round trip p50 / p99 | statuses | errors |",
            "|" + "---|" * (9 if split else 7),
            row + f" {ms(r['rtt_p50_us'])} / {ms(r['rtt_p99_us'])} | {statuses} | {r['errors']} |"]


def soak_table(rows, _arg):
    r = rows[0]

    def counts(d):
        return ", ".join(f"{k} {v}" for k, v in sorted(d.items()) if v) or "none"
    snaps = r["snapshots"]
    return ["| figure | value |", "|---|---|",
            f"| run | {r['duration_s']:.0f} s, feeds {r['feed_rate_hz']:.0f} Hz, queries asked at {r['query_rate_hz']:.0f}/s |",
            f"| queries sent / answered / timed out | {r['queries']} / {r['answered']} / {r['timeouts']} |",
            f"| statuses | {counts(r['statuses'])}; failures: {counts(r['errors'])} |",
            "| snapshots published / received / accepted | " + "; ".join(
                f"{side} {snaps['published'][side]} / {snaps['received'][side]} / {snaps['accepted'][side]}"
                for side in ["robot", "human"]) + " |",
            f"| rejected | {counts(r['rejected'])} |",
            f"| round trip p50 / p99 / p99.9 / max | {ms(r['rtt_p50_us'])} / {ms(r['rtt_p99_us'])} / "
            f"{ms(r['rtt_p999_us'])} / {ms(r['rtt_max_us'])} |",
            f"| matcher RSS after warm-up / at the end | {r['rss_start_kb']} kB / {r['rss_end_kb']} kB "
            f"({r['rss_growth_kb']:+d} kB) |"]


def remote_table(rows, _arg):
    r = rows[0]
    out = percentiles(r, [("remote", f"over Zenoh ({r.get('encoding', '?')}), vref-bridge"),
                          ("local", "local iceoryx2, same matcher"),
                          ("zenoh", "bare Zenoh: an echo queryable, no matcher")])
    out.append("")
    out.append(f"The bridge adds {ms(r['added_p50_us'])} at p50 and {ms(r['added_p99_us'])} at p99 "
               f"({r['rate_hz']:.0f} ticks/s for {r['duration_s']:.0f} s, loopback).")
    if "bridge_over_zenoh_p50_us" in r:
        out.append(f"Over the bare Zenoh round trip it adds {ms(r['bridge_over_zenoh_p50_us'])} at p50 and "
                   f"{ms(r['bridge_over_zenoh_p99_us'])} at p99.")
    return out


def python_table(rows, _arg):
    r = rows[0]
    return ["| client | cached p50 | cached p99 | first answer from a new solution p50 | count |",
            "|---|---|---|---|---|",
            f"| Python `vref_client` | {ms(r['python']['cached_p50_us'])} | {ms(r['python']['cached_p99_us'])} | "
            f"{ms(r['python']['solve_p50_us'])} | {r['python']['cached_count']} |",
            f"| Rust `ReferenceClient` | {ms(r['rust']['cached_p50_us'])} | {ms(r['rust']['cached_p99_us'])} | "
            f"{ms(r['rust']['solve_p50_us'])} | {r['rust']['cached_count']} |",
            "", f"Python / Rust cached p50: {r['ratio_cached_p50']:.2f}."] + wake_line(r)


def wake_line(r):
    w = r.get("wake")
    if not w:
        return []
    return ["", f"One Python step (two ctypes field stores) right after sleeping {w['slept_ms']:g} ms: "
                f"{w['after_sleep_p50_us']:.1f} us at p50; the same step again at once: "
                f"{w['again_p50_us']:.2f} us (services stopped)."]


def perception_table(rows, _arg):
    out = ["| BOP preset | images | objects | front end median (p99) per image | PNG decode median (p99) |",
           "|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {r['dataset']} | {r['images']} | {r['objects']} | {ms(r['median_us'])} ({ms(r['p99_us'])}) | "
                   f"{ms(r['decode_median_us'])} ({ms(r['decode_p99_us'])}) |")
    return out


def pygmtools_table(rows, arg):
    """pygmtools' full solve beside vref's, on the same scenes (ARG: vref's solver file)."""
    vref = {}
    if arg and os.path.exists(arg):
        for r in lines(arg):
            if r["mode"] == "full":
                vref[(r["method"], r["tier"], r["objects"])] = r["median_us"]
    sizes = sorted({r["objects"] for r in rows})
    out = ["| solver | " + " | ".join(f"{s} objects" for s in sizes) + " |", "|---|" + "---|" * len(sizes)]
    for method in ["sm", "rrwm"]:
        for tier in ["exact", "live"]:
            if any((method, tier, s) in vref for s in sizes):
                out.append(f"| vref {method}, {tier} tier | " + " | ".join(
                    ms(vref[(method, tier, s)]) if (method, tier, s) in vref else "-" for s in sizes) + " |")
        for params, label in [("algorithms", "ALGORITHMS.md's iteration caps"), ("defaults", "its defaults")]:
            cells = {r["objects"]: r for r in rows if r["method"] == method and r["params"] == params}
            if cells:
                out.append(f"| pygmtools {method}, {label} | " + " | ".join(
                    f"{ms(cells[s]['total_median_us'])} (acc. {cells[s]['accuracy']:.2f})" if s in cells else "-"
                    for s in sizes) + " |")
    return out


def recording_table(rows, _arg):
    out = ["| format | MB per minute | measured over |", "|---|---|---|"]
    names = {"mcap": "MCAP (`vref record --out F.mcap`: raw and Foxglove channels, zstd)",
             "vrec": "vref's own (`--out F.vrec`: bincode, uncompressed)"}
    for r in rows:
        out.append(f"| {names.get(r['format'], r['format'])} | {r['mb_per_minute']:.2f} | {r['seconds']:.0f} s |")
    return out


def bop_table(rows, arg):
    """Every method on two files side by side (ARG: the second file)."""
    second = lines(arg) if arg and os.path.exists(arg) else []
    label = lambda rs: name(rs[0]["dataset"]) if rs else "?"
    out = [f"| method | {label(rows)} accuracy / precision | {label(second)} accuracy / precision |",
           "|---|---|---|"]
    other = {r["method"]: r for r in second}
    for r in rows:
        o = other.get(r["method"])
        cell = f"{o['accuracy']:.3f} / {o['precision']:.3f}" if o else "-"
        out.append(f"| {r['method']} | {r['accuracy']:.3f} / {r['precision']:.3f} | {cell} |")
    return out


def compare_table(rows, arg):
    """Two `vref bench query` runs side by side: FILE without, ARG with a viewer."""
    out = ["| run | cached p50 / p99 | bare p50 / p99 | cached / bare p99 | every answer / bare p99 | timeouts |",
           "|---|---|---|---|---|---|"]
    for label, path in [("without a viewer", None), ("with `vref view`", arg)]:
        r = rows[0] if path is None else (lines(path)[0] if path and os.path.exists(path) else None)
        if r is None:
            out.append(f"| {label} | not measured | | | | |")
            continue
        ratio = r.get("ratio_p99")
        out.append(f"| {label} | {ms(r['cached_p50_us'])} / {ms(r['cached_p99_us'])} | {ms(r['bare_p50_us'])} / "
                   f"{ms(r['bare_p99_us'])} | {ratio if ratio is None else f'{ratio:.2f}'} | "
                   f"{r['ratio_all_p99']:.2f} | {r['timeouts']} |")
    return out


# The published figures of learned methods (../shared/data/osd/PROVENANCE.md):
# on the original OSD's labels, not the ones vref is scored on.
PUBLISHED_OSD = [("MSMFormer, first stage (learned, GPU)", 0.828, 0.606, 0.794),
                 ("UOIS-Net-3D (learned, GPU)", 0.833, 0.712, None)]


def segment_table(rows, _arg):
    """`vref bench segment --json` on the OSD learn set, beside the published learned figures."""
    out = ["| segmenter | labels | images | overlap F | boundary F | %75 | time per frame (median) |",
           "|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| vref (classical, one CPU core) | OSD learn set, as in ../shared/data/osd | {r['images']} | "
                   f"{r['overlap_f']:.3f} | {r['boundary_f']:.3f} | {r['p75']:.3f} | {ms(r['median_us'])} |")
    for label, overlap, boundary, p75 in PUBLISHED_OSD:
        p = "-" if p75 is None else f"{p75:.3f}"
        out.append(f"| {label} | original OSD, **not the same labels** | | {overlap:.3f} | {boundary:.3f} | {p} | |")
    return out


def camera_bop_table(rows, _arg):
    """`vref eval --method rigid` on the BOP scenes imported with --segment, one row per file."""
    out = ["| set (vref's own segments) | scenes | method | accuracy | precision | recall | ECE |",
           "|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {name(r['dataset'])} | {r['scenes']} | {r['method']} | {r['accuracy']:.3f} | "
                   f"{r['precision']:.3f} | {r['recall']:.3f} | {r['ece']:.3f} |")
    return out


KINDS = {"compare": compare_table, "bop": bop_table, "recording": recording_table, "pygmtools": pygmtools_table, "method": method_table, "coincidence": coincidence_table, "accuracy": accuracy_table, "families": families_table, "targets": targets_table,
         "cmu": cmu_table, "solver": solver_table, "query": query_table, "demo": demo_table,
         "soak": soak_table, "remote": remote_table, "python": python_table, "perception": perception_table,
         "segment": segment_table, "camera-bop": camera_bop_table}


def render(spec):
    kind, *rest = spec.split()
    file = rest[0] if rest else "docs/results/method-*.json"
    arg = rest[1] if len(rest) > 1 else None
    if kind not in KINDS:
        raise SystemExit(f"tables.py: unknown table kind '{kind}' (known: {', '.join(KINDS)})")
    if rest and not os.path.exists(file):
        return f"Not measured: `{file}` is missing (run `bash tools/reproduce.sh`).\n"
    rows = lines(file) if rest else []
    body = KINDS[kind](rows, arg)
    files = " and ".join(f"`{f}`" for f in rest if f.startswith("docs/")) or f"`{file}`"
    return f"From {files} (`tools/reproduce.sh`{run_note()}):\n\n" + "\n".join(body) + "\n"


def main(argv):
    check = "--check" in argv
    changed = []
    for path in [a for a in argv if a != "--check"]:
        with open(path) as f:
            text = f.read()
        new = BLOCK.sub(lambda m: m.group(1) + render(m.group("spec")) + m.group(4), text)
        if new != text:
            changed.append(path)
            if not check:
                with open(path, "w") as f:
                    f.write(new)
    if check and changed:
        print("tables out of date: " + ", ".join(changed), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
