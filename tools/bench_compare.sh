#!/usr/bin/env bash
# Before/after simulator speed: runs two carril_sim builds N times each (default 9) on each
# scenario, interleaved run by run (old, new, old, new, ...) and pinned to one core, so machine
# load hits both alike; prints per scenario the median real-time factor and tick compute p99 of
# each, and the new/old ratio of the medians.
# Usage: tools/bench_compare.sh OLD_CARRIL_SIM NEW_CARRIL_SIM [N] [scenario.yaml ...]
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: tools/bench_compare.sh OLD_SIM NEW_SIM [N] [scenario.yaml ...]" >&2; exit 2; }
old=$1 new=$2
shift 2
n=${1:-9}
shift || true
cd "$(dirname "$0")/.."
scenarios=("$@")
[ ${#scenarios[@]} -gt 0 ] || scenarios=(scenarios/square.yaml scenarios/circle.yaml)
for b in "$old" "$new"; do [ -x "$b" ] || { echo "bench_compare: $b is not executable" >&2; exit 2; }; done
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
field() { sed -n "s/^  \"$1\": \([^,]*\),*$/\1/p" "$2"; }
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
for i in $(seq "$n"); do
  for s in "${scenarios[@]}"; do
    name=$(basename "$s" .yaml)
    taskset -c 0 "$old" --scenario "$s" --out "$out/old.$name.$i" --quiet >/dev/null || true
    taskset -c 0 "$new" --scenario "$s" --out "$out/new.$name.$i" --quiet >/dev/null || true
  done
done
printf "%-10s %5s %10s %10s %8s %14s %14s %8s\n" scenario runs rtf_old rtf_new ratio p99_old_us p99_new_us ratio
for s in "${scenarios[@]}"; do
  name=$(basename "$s" .yaml)
  med() { for i in $(seq "$n"); do field "$2" "$out/$1.$name.$i/summary.json"; done | median; }
  ro=$(med old real_time_factor) rn=$(med new real_time_factor)
  po=$(med old tick_compute_p99_us) pn=$(med new tick_compute_p99_us)
  printf "%-10s %5d %10.1f %10.1f %8.3f %14.1f %14.1f %8.3f\n" "$name" "$n" "$ro" "$rn" \
    "$(awk "BEGIN {print $rn / $ro}")" "$po" "$pn" "$(awk "BEGIN {print $pn / $po}")"
done
