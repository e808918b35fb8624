#!/usr/bin/env bash
# The sanitizer check, run by hand (it takes about 25 minutes on 2 cores, too long for the README's
# test command): builds the host-debug preset (Debug, asserts on, AddressSanitizer and
# UndefinedBehaviorSanitizer, every UBSan report fatal), runs its unit tests, then every scenario
# in scenarios/ at one seed with the sanitized simulator and with the release one, and compares
# their trajectory.csv byte for byte (the same run at -O0 and -O2: a difference is undefined
# behaviour or an uninitialised read that the sanitizers did not name).
# Usage: tools/sanitize_check.sh [SEED] [OUT_DIR]    (docs/robustness.md, "The sanitizer build")
set -euo pipefail
cd "$(dirname "$0")/.."
seed=${1:-1}
out=${2:-$(mktemp -d /tmp/carril_sanitize.XXXXXX)}
mkdir -p "$out"
jobs=$(nproc)

cmake --preset host-debug > "$out/configure.log"
cmake --build build/host-debug -j"$jobs" > "$out/build-debug.log" 2>&1 ||
  { tail -30 "$out/build-debug.log"; echo "sanitize_check: the host-debug build failed"; exit 1; }
cmake --preset host > /dev/null
cmake --build build/host -j"$jobs" --target carril_sim > "$out/build-release.log" 2>&1 ||
  { tail -30 "$out/build-release.log"; echo "sanitize_check: the host build failed"; exit 1; }

failed=0
if ! ctest --test-dir build/host-debug -L unit -j"$jobs" --timeout 900 > "$out/unit.log" 2>&1; then
  grep -A40 "tests failed" "$out/unit.log" || tail -30 "$out/unit.log"
  failed=1
fi
grep "tests passed" "$out/unit.log" | sed 's/^/unit tests (sanitized): /'

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
debug=build/host-debug/host_sim/app/carril_sim
release=build/host/host_sim/app/carril_sim
n=0 bad=0
for f in scenarios/*.yaml; do
  name=$(basename "$f" .yaml)
  n=$((n + 1))
  drc=0 rrc=0
  "$debug" --scenario "$f" --seed "$seed" --quiet --out "$out/debug/$name" > "$out/$name.debug.txt" 2>&1 || drc=$?
  "$release" --scenario "$f" --seed "$seed" --quiet --out "$out/release/$name" > "$out/$name.release.txt" 2>&1 || rrc=$?
  reports=$(grep -c -E "ERROR: AddressSanitizer|runtime error:|ERROR: LeakSanitizer" "$out/$name.debug.txt" || true)
  if cmp -s "$out/debug/$name/trajectory.csv" "$out/release/$name/trajectory.csv"; then same=equal; else same=DIFFERENT; fi
  verdict=ok
  if [[ $reports != 0 || $drc != "$rrc" || $same != equal ]]; then verdict=FAIL; bad=$((bad + 1)); fi
  printf '%-36s sanitizer reports %s, exit %s (release %s), trajectory.csv %s: %s\n' \
    "$name" "$reports" "$drc" "$rrc" "$same" "$verdict"
done
echo "sanitize_check: $((n - bad)) of $n scenarios clean at seed $seed (outputs in $out)"
[[ $bad == 0 && $failed == 0 ]]
