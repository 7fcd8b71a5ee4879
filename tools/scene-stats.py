#!/usr/bin/env python3
"""What limits accuracy on a dataset file, independent of any method.

    python3 tools/scene-stats.py DATASET.jsonl [--partnered-only OUT.jsonl]

Prints, over the file's scenes:
- the mean number of human and robot objects and the share of human
  objects without a partner;
- the accuracy ceiling of a method that gives every human object a partner
  whenever the robot view has one to give (all four methods do: Hungarian
  assignment of the smaller side), with every partner right;
- the share of partnered human objects whose true partner is not the most
  similar robot object by appearance (cosine of the features), i.e. where
  appearance alone must fail.

--partnered-only writes the file with every object that has no partner
removed from both views, to measure the methods without outliers.
"""
import argparse
import json
import math


def cosine(a, b):
    na = math.sqrt(sum(x * x for x in a))
    nb = math.sqrt(sum(y * y for y in b))
    if na == 0 or nb == 0:
        return 1.0  # ALGORITHMS.md: no information
    return sum(x * y for x, y in zip(a, b)) / (na * nb)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dataset")
    parser.add_argument("--partnered-only", metavar="OUT")
    args = parser.parse_args()

    scenes = [json.loads(line) for line in open(args.dataset) if line.strip()]
    if not scenes:
        raise SystemExit(f"{args.dataset} holds no scenes")
    humans = robots = unpartnered = partnered = ambiguous = 0
    ceiling = 0.0
    for scene in scenes:
        human = scene["human"]["objects"]
        robot = scene["robot"]["objects"]
        truth = {h: r for h, r in scene["ground_truth"]}
        n, m, g = len(human), len(robot), len(truth)
        humans += n
        robots += m
        unpartnered += n - g
        # With n > m, n - m human objects stay unmatched: at best exactly
        # the ones without a partner.
        ceiling += (g + max(0, n - m)) / n
        features = {o["id"]: o.get("feature") or [] for o in robot}
        for o in human:
            if o["id"] not in truth:
                continue
            partnered += 1
            mine = o.get("feature") or []
            right = cosine(mine, features[truth[o["id"]]])
            if any(cosine(mine, f) >= right for i, f in features.items() if i != truth[o["id"]]):
                ambiguous += 1
    k = len(scenes)
    print(f"{args.dataset}: {k} scenes")
    print(f"  objects per view: human {humans / k:.2f}, robot {robots / k:.2f}")
    print(f"  human objects without a partner: {unpartnered / humans:.3f}")
    print(f"  accuracy ceiling when every human object gets a partner it can: {ceiling / k:.3f}")
    print(f"  partnered human objects whose partner is not the most similar: {ambiguous / max(partnered, 1):.3f}")

    if args.partnered_only:
        with open(args.partnered_only, "w") as out:
            for scene in scenes:
                keep_h = {h for h, _ in scene["ground_truth"]}
                keep_r = {r for _, r in scene["ground_truth"]}
                for side, keep in (("human", keep_h), ("robot", keep_r)):
                    scene[side]["objects"] = [o for o in scene[side]["objects"] if o["id"] in keep]
                out.write(json.dumps(scene) + "\n")


if __name__ == "__main__":
    main()
