"""Writes config/vref.toml with `[matching.rigid]` settings replaced:

    python3 tools/rigid-settings.py 'key = value\\nkey = value' OUT.toml

Each setting must already be in that table (a misspelt key is refused,
not added). Shared by tools/gravity.sh and tools/one-up.sh."""
import re
import sys

settings, out = sys.argv[1].encode().decode("unicode_escape"), sys.argv[2]
text = open("config/vref.toml").read()
head, sep, rest = text.partition("[matching.rigid]")
body, nxt, tail = rest.partition("\n[")
for line in filter(None, (l.strip() for l in settings.splitlines())):
    key = line.split("=")[0].strip()
    body, n = re.subn(rf"(?m)^{re.escape(key)}\s*=.*$", line, body, count=1)
    if n == 0:
        sys.exit(f"rigid-settings.py: no {key} in [matching.rigid]")
open(out, "w").write(head + sep + body + nxt + tail)
