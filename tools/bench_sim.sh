#!/usr/bin/env bash
# Simulator speed: runs carril_sim N times (default 7) on each scenario, pinned to one core, and
# prints the median, min and max real-time factor and the firmware tick's compute p50/p99 from
# summary.json. Camera 30 Hz, lidar 20 Hz, control 100 Hz (the presets' rates).
# Usage: tools/bench_sim.sh [N] [scenario.yaml ...]   (build the host preset first)
# CARRIL_SIM picks another carril_sim, e.g. the fast simulator's (tools/build_fast_sim.sh):
# CARRIL_SIM=build/sim-pgo/host_sim/app/carril_sim tools/bench_sim.sh 15 scenarios/square.yaml
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-7}
shift || true
scenarios=("$@")
[ ${#scenarios[@]} -gt 0 ] || scenarios=(scenarios/square.yaml scenarios/circle.yaml)
sim=${CARRIL_SIM:-./build/host/host_sim/app/carril_sim}
[ -x "$sim" ] || { echo "bench_sim: build first: cmake --preset host && cmake --build --preset host" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
field() { sed -n "s/^  \"$1\": \([^,]*\),*$/\1/p" "$2"; }
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
printf "%-10s %5s %12s %10s %10s %10s %12s %12s\n" scenario runs sim_s "rtf_med" "rtf_min" "rtf_max" "tick_p50_us" "tick_p99_us"
# Interleave the scenarios run by run, so machine load hits them alike.
for i in $(seq "$n"); do
  for s in "${scenarios[@]}"; do
    name=$(basename "$s" .yaml)
    taskset -c 0 "$sim" --scenario "$s" --out "$out/$name.$i" --quiet >/dev/null || true
  done
done
for s in "${scenarios[@]}"; do
  name=$(basename "$s" .yaml)
  rtf=$(for i in $(seq "$n"); do field real_time_factor "$out/$name.$i/summary.json"; done)
  p50=$(for i in $(seq "$n"); do field tick_compute_p50_us "$out/$name.$i/summary.json"; done | median)
  p99=$(for i in $(seq "$n"); do field tick_compute_p99_us "$out/$name.$i/summary.json"; done | median)
  simt=$(field sim_time_s "$out/$name.1/summary.json")
  printf "%-10s %5d %12s %10.0f %10.0f %10.0f %12s %12s\n" "$name" "$n" "$simt" \
    "$(echo "$rtf" | median)" "$(echo "$rtf" | sort -g | head -1)" "$(echo "$rtf" | sort -g | tail -1)" "$p50" "$p99"
done
