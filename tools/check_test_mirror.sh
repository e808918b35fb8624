#!/usr/bin/env bash
# tests/unit mirrors the source tree: every folder under tests/unit/ is named after a source
# folder (firmware/<x>, host_sim/<x>, or the top-level hal and loader), and a test named after a
# source file (<Name>Test.cpp for <Name>.hpp) sits in the folder of that source. Prints each
# misplaced file and exits 1 when there is one.
# Usage: tools/check_test_mirror.sh [SOURCE_DIR]
set -uo pipefail
cd "${1:-$(dirname "$0")/..}" || exit 2
bad=0
for d in tests/unit/*/; do
  d=${d%/}
  name=${d#tests/unit/}
  if [ "$name" != hal ] && [ "$name" != loader ] && [ ! -d "firmware/$name" ] &&
    [ ! -d "host_sim/$name" ]; then
    echo "test mirror: $d has no source folder firmware/$name, host_sim/$name, hal or loader"
    bad=1
  fi
done
while IFS= read -r t; do
  base=$(basename "$t" Test.cpp)
  mapfile -t srcs < <(find firmware hal host_sim loader -name "$base.hpp" 2>/dev/null)
  [ ${#srcs[@]} -eq 1 ] || continue  # not named after one source file
  src=${srcs[0]}
  case $src in
    hal/*) want=hal ;;
    loader/*) want=loader ;;
    *) want=$(basename "$(dirname "$src")") ;;
  esac
  have=$(basename "$(dirname "$t")")
  if [ "$have" != "$want" ]; then
    echo "test mirror: $t tests $src, so it belongs in tests/unit/$want/"
    bad=1
  fi
done < <(find tests/unit -name '*Test.cpp' | sort)
if [ $bad -eq 0 ]; then echo "test mirror: tests/unit mirrors the source tree"; fi
exit $bad
