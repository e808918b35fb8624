#!/usr/bin/env bash
# The libFuzzer targets of tests/fuzz (the fuzz preset: clang, ASan, UBSan).
#   tools/fuzz.sh short            configure, build, and the short deterministic runs (CTest)
#   tools/fuzz.sh long SECONDS [TARGET...]
#                                  each target (default: all) for SECONDS, one after the other,
#                                  from its seeds and regressions; the inputs it adds are kept in
#                                  build/fuzz/long/<target>/corpus (a later run goes on from them)
# A long run prints one line per target: runs, exec/s, corpus size, and crash/leak/timeout files
# (build/fuzz/long/<target>/artifacts/); its full log is build/fuzz/long/<target>.log.
# Exit status: 0 when nothing was found.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:-short}
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j2 >/dev/null
if [ "$mode" = short ]; then
  exec ctest --preset fuzz
fi
[ "$mode" = long ] || { echo "usage: tools/fuzz.sh short | long SECONDS [TARGET...]" >&2; exit 2; }
seconds=${2:?seconds}
shift 2
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  mapfile -t targets < <(cd build/fuzz/tests/fuzz && ls fuzz_* | sed 's/^fuzz_//' | sort)
fi
rc=0
for t in "${targets[@]}"; do
  out=build/fuzz/long/$t
  mkdir -p "$out/corpus" "$out/artifacts"
  log=build/fuzz/long/$t.log
  set +e
  "build/fuzz/tests/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$out/artifacts/" "$out/corpus" "tests/fuzz/$t" \
    >"$log" 2>&1
  status=$?
  set -e
  stat() { grep -E "^stat::$1:" "$log" | awk '{print $2}' | tail -1; }
  found=$(ls "$out/artifacts" | wc -l)
  printf '%-16s exit %d, %s runs in %s s, %s exec/s, corpus %s files, %s new; artifacts: %s\n' \
    "$t" "$status" "$(stat number_of_executed_units)" "$seconds" "$(stat average_exec_per_sec)" \
    "$(ls "$out/corpus" | wc -l)" "$(stat new_units_added)" "$found"
  if [ "$status" -ne 0 ] || [ "$found" -ne 0 ]; then rc=1; fi
done
exit $rc
