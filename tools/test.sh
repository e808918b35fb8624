#!/usr/bin/env bash
# Every test: install what is missing, build the host preset, run all of CTest (unit, simulator,
# scenario and CLI tests), then cross-build firmware/ and hal/ for aarch64 and run the robot
# target's smoke test under qemu.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
jobs=$(nproc)
echo "== host: configure, build, test"
cmake --preset host >/dev/null
cmake --build --preset host -j"$jobs"
ctest --preset host -j"$jobs"
echo "== aarch64: cross-build firmware, hal and the robot target; smoke test under qemu"
cmake --preset aarch64 >/dev/null
cmake --build --preset aarch64 -j"$jobs"
ctest --preset aarch64
