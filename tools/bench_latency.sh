#!/usr/bin/env bash
# Wake latency of carril_controller's control loop against rt-tests' cyclictest, at the same
# period (the robot's control rate) and SCHED_FIFO priority, one after the other in the same run
# (issue 9 item 10; docs/performance.md). carril_controller runs the bench controller file (no
# CAN, no sensors: the loop, the firmware and the slow group as on the robot).
# Usage: tools/bench_latency.sh [LOOPS] [ROUNDS]   (default 2000 loops at 100 Hz = 20 s, 2 rounds)
# Prints per round both p50/p99/max [us] and the p99 ratio carril / cyclictest; the median ratio.
set -euo pipefail
cd "$(dirname "$0")/.."
loops=${1:-2000}
rounds=${2:-2}
ctl=build/host/targets/controller/carril_controller
[ -x "$ctl" ] || { echo "bench_latency: build first (cmake --build --preset host)" >&2; exit 2; }
command -v cyclictest >/dev/null || { echo "bench_latency: cyclictest missing (rt-tests)" >&2; exit 2; }
prio=50
interval_us=10000  # campero's control_rate_hz 100
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ratios=()
for r in $(seq 1 "$rounds"); do
  "$ctl" --robot config/robots/campero.yaml --controller config/controller/bench.yaml \
    --mission config/missions/follow_line.yaml --ticks "$loops" >"$tmp/ctl.txt"
  # "loop: periods N, ...; wake latency p50 A us, p99 B us, max C us; ..."
  read -r c50 c99 cmax < <(grep -m1 -E '^loop: periods [0-9]+, .*wake latency' "$tmp/ctl.txt" |
    sed -E 's/.*wake latency p50 ([0-9.]+) us, p99 ([0-9.]+) us, max ([0-9.]+) us.*/\1 \2 \3/')
  policy=$(grep -o 'control loop SCHED_[A-Z]*' "$tmp/ctl.txt" | head -1)
  cyclictest -p "$prio" -i "$interval_us" -l "$loops" -m -q -h 10000 >"$tmp/cyc.txt" 2>&1
  # Histogram lines "US COUNT": percentiles from the cumulative count.
  read -r y50 y99 ymax < <(awk '/^[0-9]+ [0-9]+$/ { n[$1+0] += $2; tot += $2 }
    /# Max Latencies:/ { mx = $4 + 0 }
    END { c = 0; p50 = -1; p99 = -1
      for (us = 0; us <= 10000; us++) { c += n[us]
        if (p50 < 0 && c >= 0.50 * tot) p50 = us
        if (p99 < 0 && c >= 0.99 * tot) p99 = us }
      print p50, p99, mx }' "$tmp/cyc.txt")
  ratio=$(awk -v a="$c99" -v b="$y99" 'BEGIN { printf "%.2f", (b > 0 ? a / b : 0) }')
  ratios+=("$ratio")
  echo "round $r: carril_controller ($policy $prio, $loops periods of $interval_us us) wake p50 $c50 us, p99 $c99 us, max $cmax us; cyclictest -p $prio -i $interval_us -l $loops -m: p50 $y50 us, p99 $y99 us, max $ymax us; p99 ratio $ratio"
done
median=$(printf '%s\n' "${ratios[@]}" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }')
echo "bench_latency: median p99 ratio carril/cyclictest over $rounds rounds: $median (goal <= 1.2)"
