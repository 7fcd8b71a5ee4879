#!/usr/bin/env bash
# What `rigid` answers when an object moved between the two views
# (docs/method.md, "An object that moved"): in every scene of the vref-sim
# training files with up vectors (seeds 100-102, tools/gravity.sh's), one
# human object with a partner is moved D metres (default 0.2) along the
# table (a random direction across the view's up), the other objects
# untouched; then the moved objects' answers, and the `ok` answers with a
# wrong partner among the others, as they are and after the move.
#
#   bash tools/carryover-data.sh && bash tools/gravity.sh && bash tools/moved-object.sh [D]
#
# Needs `cargo build --release -p vref --bins` first.
set -euo pipefail
cd "$(dirname "$0")/.."
. tools/need-vref.sh
dir=${VREF_CARRY_DIR:-target/carry}/up
distance=${1:-0.2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| training file | moved objects: right partner (of them ok) | no partner | wrong partner (of them ok) | other objects' wrong ok, unmoved | after the move |"
echo "|---|---|---|---|---|---|"
for f in moi100 moi101 moi102 mrc100 mrc101 mrc102; do
  [ -s "$dir/$f.jsonl" ] || { echo "$dir/$f.jsonl missing: run tools/gravity.sh first" >&2; exit 1; }
  python3 - "$dir/$f.jsonl" "$work/moved.jsonl" "$distance" <<'PY'
import json, math, random, sys
source, target, distance = sys.argv[1], sys.argv[2], float(sys.argv[3])
rng = random.Random(7)
moved = {}
with open(target, "w") as out:
    for line in open(source):
        pair = json.loads(line)
        human = pair["human"]
        up = human["up"]
        partnered = sorted(h for h, _ in pair["ground_truth"])
        if partnered:
            h = rng.choice(partnered)
            while True:
                v = [rng.gauss(0.0, 1.0) for _ in range(3)]
                along = sum(a * b for a, b in zip(v, up))
                v = [a - along * b for a, b in zip(v, up)]
                norm = math.sqrt(sum(a * a for a in v))
                if norm > 1e-6:
                    break
            for o in human["objects"]:
                if o["id"] == h:
                    o["position"] = [p + distance * a / norm for p, a in zip(o["position"], v)]
            moved[pair["name"]] = h
        out.write(json.dumps(pair) + "\n")
json.dump(moved, open(target + ".moved", "w"))
PY
  "$vref" eval --dataset "$dir/$f.jsonl" --method rigid --answers "$work/before.jsonl" > /dev/null
  "$vref" eval --dataset "$work/moved.jsonl" --method rigid --answers "$work/after.jsonl" > /dev/null
  python3 - "$f" "$work/moved.jsonl" "$work/before.jsonl" "$work/after.jsonl" <<'PY'
import json, sys
name, data, before, after = sys.argv[1:]
names = [json.loads(l)["name"] for l in open(data)]
moved = json.load(open(data + ".moved"))
def rows(path):
    return [json.loads(l) for l in open(path)]
def is_moved(r):
    return moved.get(names[r["scene"]]) == r["human_object"]
def wrong_ok(rs):
    return sum(r["status"] == "ok" and not r["correct"] for r in rs if not is_moved(r))
b, a = rows(before), rows(after)
m = [r for r in a if is_moved(r)]
right = [r for r in m if r["correct"]]
none = [r for r in m if r["partner"] is None]
wrong = [r for r in m if r["partner"] is not None and not r["correct"]]
ok = lambda rs: sum(r["status"] == "ok" for r in rs)
print("| %s | %d (%d) | %d | %d (%d) | %d | %d |" % (name, len(right), ok(right), len(none),
      len(wrong), ok(wrong), wrong_ok(b), wrong_ok(a)))
PY
done
