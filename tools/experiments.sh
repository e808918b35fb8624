#!/usr/bin/env bash
# The thesis experiments: runs the whole matrix (5 scenarios x 4 robot/strategy combinations,
# listed by tools/experiments_report.py) with the built carril_sim, copies each run's plots to
# docs/img/<scenario>_<preset>_<strategy>_{trajectory,velocities}.png and regenerates
# docs/experiments.md from the runs' summary.json files (its hand-written discussion is kept).
#
# Usage: bash tools/experiments.sh [BUILD_DIR]     (default build/host; carril_sim must be built:
#        cmake --preset host && cmake --build --preset host --target carril_sim)
# Runs go to BUILD_DIR/runs/<scenario>_<preset>_<strategy>/, as the experiment.* CTest tests.
# A run that misses its expectations is a result like any other and is reported; the exit status
# is 0 when every run left its outputs and the report was written, 1 when some run left none
# (crash, bad input), 2 when nothing could be run or the report could not be written.
set -uo pipefail
build=""
if [ $# -gt 1 ]; then
  echo "usage: bash tools/experiments.sh [BUILD_DIR]" >&2
  exit 2
fi
# A build directory given on the command line is relative to where the script is called from.
if [ $# -eq 1 ]; then
  build=$(cd "$1" 2>/dev/null && pwd) || {
    echo "experiments: no build directory $1" >&2
    exit 2
  }
fi
cd "$(dirname "$0")/.." || exit 2
build=${build:-build/host}
sim=$build/host_sim/app/carril_sim
if [ ! -x "$sim" ]; then
  echo "experiments: $sim not found; build it first (cmake --preset host &&" \
    "cmake --build --preset host --target carril_sim) or pass the build directory" >&2
  exit 2
fi
runs=$build/runs
img=docs/img
mkdir -p "$runs" "$img" || exit 2
status=$(mktemp "$runs/.experiments-status.XXXXXX") || exit 2
errs=$(mktemp "$runs/.experiments-stderr.XXXXXX") || exit 2
outs=$(mktemp "$runs/.experiments-stdout.XXXXXX") || exit 2
trap 'rm -f "$status" "$errs" "$outs"' EXIT

matrix=$(python3 tools/experiments_report.py matrix) || exit 2

# Copies src to dst whole: a temporary file in dst's directory, then rename.
copy_whole() {
  local tmp
  tmp=$(mktemp "$(dirname "$2")/.$(basename "$2").XXXXXX") || return 1
  if cp "$1" "$tmp" && chmod 644 "$tmp" && mv -f "$tmp" "$2"; then return 0; fi
  rm -f "$tmp"
  return 1
}

total=0
passed=0
failed=0
missing=0
while read -r scenario preset strategy; do
  [ -n "$scenario" ] || continue
  id=${scenario}_${preset}_${strategy}
  out=$runs/$id
  total=$((total + 1))
  # A result left by an earlier run must not pass for this one's.
  rm -rf "$out"
  "$sim" --scenario "scenarios/$scenario.yaml" --preset "$preset" --strategy "$strategy" \
    --out "$out" --quiet >"$outs" 2>"$errs"
  rc=$?
  line=$(grep -m1 "^carril_sim: $scenario:" "$outs" | sed 's/^carril_sim: //')
  msg=$(tr '\n' ' ' <"$errs" | sed 's/  */ /g; s/ $//' | cut -c1-300)
  echo "$scenario $preset $strategy $rc $msg" >>"$status"
  case $rc in
    0) passed=$((passed + 1)) ;;
    1) failed=$((failed + 1)) ;;
    *) missing=$((missing + 1)) ;;
  esac
  # carril_sim's result line without its "carril_sim: <scenario>: " prefix.
  if [ "$rc" -le 1 ] && [ -n "$line" ]; then
    printf 'experiments: %-36s %s\n' "$id" "${line#*: }"
  else
    printf 'experiments: %-36s NO OUTPUT (exit %s)%s\n' "$id" "$rc" "${msg:+: $msg}"
  fi
  for kind in trajectory velocities; do
    dst=$img/${id}_${kind}.png
    if [ "$rc" -le 1 ] && [ -s "$out/$kind.png" ]; then
      copy_whole "$out/$kind.png" "$dst" || echo "experiments: cannot copy $out/$kind.png to $dst" >&2
    else
      rm -f "$dst"  # no stale picture next to a run that left none
    fi
  done
done <<<"$matrix"

python3 tools/experiments_report.py report --runs "$runs" --status "$status" \
  --img-dir "$img" --out docs/experiments.md || exit 2
echo "experiments: $total runs: $passed passed, $failed did not pass, $missing left no output;" \
  "report docs/experiments.md, plots $img/"
[ "$missing" -eq 0 ]
