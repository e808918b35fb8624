#!/usr/bin/env bash
# Every test: install what is missing, build the host preset, run all of CTest (unit, simulator,
# scenario and CLI tests), then cross-build firmware/, hal/, loader/, the robot target and every
# unit test that needs no simulator for aarch64 (GoogleTest built from Debian's sources) and run
# them under qemu: one CTest per test binary, the allocation-counting test included, and the robot
# target's smoke tests; then build the libFuzzer targets (the fuzz preset: clang, ASan, UBSan) and
# run each one short and deterministically over its seeds and regressions (tests/fuzz, about
# 20 s of runs); last, build the fast simulator (tools/build_fast_sim.sh: profile-guided and
# link-time optimised) and check that its runs equal the host build's. Ends with one line:
# "carril: N passed, N failed".
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
jobs=$(nproc)
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
rc=0
echo "== host: configure, build, test"
cmake --preset host >/dev/null
cmake --build --preset host -j"$jobs"
ctest --preset host -j"$jobs" 2>&1 | tee "$logs/host.log" || rc=1
echo "== aarch64: cross-build firmware, hal, loader, the robot target and the portable unit tests; run them under qemu"
cmake --preset aarch64 >/dev/null
cmake --build --preset aarch64 -j"$jobs"
ctest --preset aarch64 -j"$jobs" 2>&1 | tee "$logs/aarch64.log" || rc=1
echo "== fuzz: build the libFuzzer targets (clang, ASan, UBSan); short deterministic runs"
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j"$jobs"
ctest --preset fuzz -j"$jobs" 2>&1 | tee "$logs/fuzz.log" || rc=1
echo "== fast simulator: profile-guided and link-time optimised build; its runs equal the host build's"
bash tools/build_fast_sim.sh
ctest --test-dir build/sim-pgo -L fast_sim 2>&1 | tee "$logs/fast_sim.log" || rc=1
# CTest's own summary: "N% tests passed, F tests failed out of T".
total=0
failed=0
for f in "$logs"/*.log; do
  line=$(grep -E 'tests passed, [0-9]+ tests failed out of [0-9]+' "$f" | tail -1) || { rc=1; continue; }
  t=$(sed -E 's/.* out of ([0-9]+).*/\1/' <<<"$line")
  x=$(sed -E 's/.*passed, ([0-9]+) tests failed.*/\1/' <<<"$line")
  total=$((total + t))
  failed=$((failed + x))
done
echo "carril: $((total - failed)) passed, $failed failed"
[ "$failed" -eq 0 ] || rc=1
exit $rc
