#!/usr/bin/env bash
# Renders an MCAP file of vref's in Foxglove Studio 1.48 (the open-source
# @foxglove/studio-base bundle from npm) in headless Chromium and saves a
# screenshot: the picture in docs/viewer.md.
#
#   tools/studio-picture/run.sh FILE.mcap OUT.png [ISO-TIME]
#
# Needs Debian's chromium and npm. ISO-TIME (e.g. 2026-12-01T20:47:49.000Z)
# is the moment shown; default: the file's start.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
mcap="$(realpath "$1")"; out="$(realpath -m "$2")"; time="${3:-}"
work="$(mktemp -d)"
trap 'kill "${server:-0}" 2>/dev/null || true; rm -rf "$work"' EXIT
cd "$work"
npm pack --silent @foxglove/studio-base@1.48.0 react@17.0.2 react-dom@17.0.2 >/dev/null
mkdir site
tar xzf foxglove-studio-base-1.48.0.tgz && mv package/assets site/assets && rm -rf package
tar xzf react-17.0.2.tgz && cp package/umd/react.production.min.js site/react.js && rm -rf package
tar xzf react-dom-17.0.2.tgz && cp package/umd/react-dom.production.min.js site/react-dom.js && rm -rf package
cp "$here"/index.html "$here"/main.js "$here"/layout.js site/
cp "$mcap" site/recording.mcap
npm install --silent playwright-core@1 >/dev/null
cp "$here"/shot.js .
port="$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
python3 "$here"/serve.py site "$port" >/dev/null 2>&1 &
server=$!
sleep 1
url="http://127.0.0.1:$port/?ds=remote-file&ds.url=http://127.0.0.1:$port/recording.mcap&layoutId=vref"
[ -n "$time" ] && url="$url&time=$time"
# Waits 15 s for the file to load, then dismisses the settings tooltip.
CLICK=1151,58 node shot.js "$url" "$out" 15000 >/dev/null
echo "$out"
