"""A dataset file with every object's appearance feature removed (positions
only), for the measurements without appearance (tools/without-features.sh,
tools/planar-ece.py).

    python3 tools/strip_features.py IN.jsonl OUT.jsonl
"""

import json
import sys


def without_features(source, target):
    with open(source) as lines, open(target, "w") as out:
        for line in lines:
            pair = json.loads(line)
            for side in ("robot", "human"):
                for o in pair[side]["objects"]:
                    o.pop("feature", None)
            out.write(json.dumps(pair) + "\n")


if __name__ == "__main__":
    without_features(sys.argv[1], sys.argv[2])
