#!/usr/bin/env bash
# The test command: the Rust workspace's tests, then the Python client's
# (clients/python) in a virtual environment of its own, against the
# service binaries the Rust tests just built (target/debug).
#
#   bash tools/test.sh
#
# Needs python3 (3.11 or newer) with the venv module, and PyPI for the
# first run (iceoryx2 0.10.0, numpy, pytest, mypy, and mcap with
# mcap-protobuf-support for tools/check-mcap.py, which tests/viewer.rs
# runs on the files it records; the ROS 2 wheels below). Set VREF_VENV to
# put the environment elsewhere (default target/python-venv).
set -euo pipefail
cd "$(dirname "$0")/.."

venv="${VREF_VENV:-target/python-venv}"
python="${PYTHON:-python3}"
if [ ! -x "$venv/bin/python" ]; then
  "$python" -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
  ./clients/python pytest==9.2.0 mypy==2.4.1 mcap==1.6.0 mcap-protobuf-support==0.6.0

# vref-ros2's test talks to a genuine ROS 2 node: rclpy and the message
# packages from the official ROS 2 (Kilted) wheels on PyPI, no ROS install
# (about 270 MB, in a venv of its own; VREF_ROS2_VENV puts it elsewhere).
# The test runs DDS inside a network namespace with loopback only, which
# needs root (unshare --net) and iproute2. The same venv holds rosbags
# (pure Python), which writes the rosbag2 files tests/rosbag.rs feeds to
# vref and reads back what `vref record --ros2` writes.
ros2_venv="${VREF_ROS2_VENV:-target/ros2-venv}"
if [ ! -x "$ros2_venv/bin/python" ]; then
  "$python" -m venv "$ros2_venv"
fi
"$ros2_venv/bin/python" -m pip install --quiet --disable-pip-version-check \
  'ros-rclpy[fastrtps]==9.1.2' ros-sensor-msgs==5.5.1 ros-geometry-msgs==5.5.1 \
  ros-visualization-msgs==5.5.1 ros-std-srvs==5.5.1 numpy==2.4.6 \
  rosbags==0.11.9

# Every service package has an integration test, so `cargo test` builds
# every executable before the system tests (tests/) start them from
# target/debug. The viewer's tests read their MCAP files with Python's
# mcap too.
# A venv's python is a symlink: resolving it would run the base
# interpreter, without the venv's packages.
VREF_PYTHON="$(cd "$venv/bin" && pwd)/python" \
  VREF_ROS2_PYTHON="$(cd "$ros2_venv/bin" && pwd)/python" cargo test --workspace --locked --no-fail-fast

# Every table of the README and docs/ is the one tools/tables.py makes from
# docs/results/: a table edited by hand, or a result file changed without
# its table, fails here.
python3 tools/tables.py --check README.md docs/*.md

# From the repository root the package under test is the installed one,
# not clients/python/src.
"$venv/bin/python" -m pytest -q -p no:cacheprovider clients/python/tests
"$venv/bin/python" -m mypy --config-file clients/python/pyproject.toml \
  clients/python/src clients/python/tests clients/python/examples
