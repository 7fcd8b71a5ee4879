#!/usr/bin/env bash
# What `rigid` answers when an object moved between the two views
# (docs/method.md, "An object that moved"): in every scene of the vref-sim
# training files with up vectors (seeds 100-102, tools/gravity.sh's), one
# human object with a partner is moved D metres (default 0.2) along the
# table (a random direction across the view's up) to a free place: no
# object of either view within 0.1 m of it (the robot's placed by the
# motion the ground truth's pairs fit); the other objects untouched.
# The same on the rendered BOP scenes' training halves (000000-000005 of
# ../shared/data/bop, imported with --world-up 0,0,1), with the dataset's
# masks and with vref's own segments. Then the moved objects' answers, and
# the `ok` answers with a wrong partner among the others, as they are and
# after the move.
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
echo "| training file | scenes with an object moved | moved objects: right partner (of them ok) | no partner | wrong partner (of them ok) | other objects' wrong ok, unmoved | after the move |"
echo "|---|---|---|---|---|---|---|"
measure() {
  local name=$1 file=$2
  python3 - "$file" "$work/moved.jsonl" "$distance" <<'PY'
import json, math, random, sys
source, target, distance = sys.argv[1], sys.argv[2], float(sys.argv[3])
FREE = 0.1
rng = random.Random(7)


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def robot_to_human(pairs):
    """The rotation and translation taking robot points onto their human
    partners (Horn's quaternion, the largest eigenvector by power steps)."""
    h = [p for p, _ in pairs]
    r = [q for _, q in pairs]
    ch = [sum(p[k] for p in h) / len(h) for k in range(3)]
    cr = [sum(q[k] for q in r) / len(r) for k in range(3)]
    s = [[sum((q[a] - cr[a]) * (p[b] - ch[b]) for p, q in zip(h, r)) for b in range(3)]
         for a in range(3)]
    (xx, xy, xz), (yx, yy, yz), (zx, zy, zz) = s
    n = [[xx + yy + zz, yz - zy, zx - xz, xy - yx],
         [yz - zy, xx - yy - zz, xy + yx, zx + xz],
         [zx - xz, xy + yx, -xx + yy - zz, yz + zy],
         [xy - yx, zx + xz, yz + zy, -xx - yy + zz]]
    shift = sum(abs(v) for row in n for v in row) + 1.0
    v = [1.0, 0.1, 0.2, 0.3]
    for _ in range(500):
        v = [sum((n[a][b] + (shift if a == b else 0.0)) * v[b] for b in range(4)) for a in range(4)]
        norm = math.sqrt(dot(v, v))
        v = [x / norm for x in v]
    w, x, y, z = v
    rot = [[w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
           [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
           [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z]]
    return lambda q: [dot(rot[a], sub(q, cr)) + ch[a] for a in range(3)]


moved = {}
with open(target, "w") as out:
    for line in open(source):
        pair = json.loads(line)
        human = pair["human"]
        up = human["up"]
        at = {o["id"]: o["position"] for o in human["objects"]}
        there = {o["id"]: o["position"] for o in pair["robot"]["objects"]}
        truth = pair["ground_truth"]
        partnered = sorted(h for h, _ in truth)
        if len(truth) >= 3:
            to_human = robot_to_human([(at[h], there[r]) for h, r in truth])
            occupied = [to_human(q) for q in there.values()]
            h = rng.choice(partnered)
            for _ in range(100):
                v = [rng.gauss(0.0, 1.0) for _ in range(3)]
                along = dot(v, up)
                v = [a - along * b for a, b in zip(v, up)]
                norm = math.sqrt(dot(v, v))
                if norm < 1e-6:
                    continue
                place = [p + distance * a / norm for p, a in zip(at[h], v)]
                others = [p for k, p in at.items() if k != h] + occupied
                if all(math.dist(place, p) >= FREE for p in others):
                    for o in human["objects"]:
                        if o["id"] == h:
                            o["position"] = place
                    moved[pair["name"]] = h
                    break
        out.write(json.dumps(pair) + "\n")
json.dump(moved, open(target + ".moved", "w"))
PY
  "$vref" eval --dataset "$file" --method rigid --answers "$work/before.jsonl" > /dev/null
  "$vref" eval --dataset "$work/moved.jsonl" --method rigid --answers "$work/after.jsonl" > /dev/null
  python3 - "$name" "$work/moved.jsonl" "$work/before.jsonl" "$work/after.jsonl" <<'PY'
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
print("| %s | %d of %d | %d (%d) | %d | %d (%d) | %d | %d |" % (name, len(moved), len(names),
      len(right), ok(right), len(none), len(wrong), ok(wrong), wrong_ok(b), wrong_ok(a)))
PY
}
for f in moi100 moi101 moi102 mrc100 mrc101 mrc102; do
  [ -s "$dir/$f.jsonl" ] || { echo "$dir/$f.jsonl missing: run tools/gravity.sh first" >&2; exit 1; }
  measure "$f" "$dir/$f.jsonl"
done
# The rendered BOP scenes' training halves, with the dataset's masks and
# with vref's own segments, each view carrying its camera's up.
bop=${VREF_BOP_SOURCE:-../shared/data/bop}
for family in table floor; do
  [ -d "$bop/$family" ] || continue
  for masks in given own; do
    flags=()
    [ "$masks" = own ] && flags=(--segment)
    "$vref" import bop "$bop/$family" --world-up 0,0,1 "${flags[@]}" --out "$work/bop.jsonl" 2>/dev/null
    grep -E '"name": *"[^"]*00000[0-5]"' "$work/bop.jsonl" > "$work/bop-train.jsonl"
    measure "bop-$family-train ($masks masks)" "$work/bop-train.jsonl"
  done
done
