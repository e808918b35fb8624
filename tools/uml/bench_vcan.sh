#!/usr/bin/env bash
# Send throughput on a real kernel's vcan0, inside one user-mode-linux boot: can-utils'
# `cangen vcan0 -g 0 -n N` against carril's SocketCanBus (carril_can_throughput -n N), R runs
# each, alternating, both timed the same way (start-up taken off); prints every run, the
# medians and the ratio carril / cangen (goal: >= 1).
# Exit 77 when user-mode-linux cannot start (tools/uml/uml_run.sh says why).
# Usage: tools/uml/bench_vcan.sh [--build DIR] [-n FRAMES] [--runs R] [--batch B]
#   --build DIR  the build tree holding bench/carril_can_throughput (default build/host)
#   --batch B    carril's SocketCanBus tx_batch, frames per sendmmsg (default 32, as
#                carril_controller; 1: one send() per frame, as cangen's one write() per frame)
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$here/../../build/host n=20000 runs=3 inside=0 batch=32
while [ $# -gt 0 ]; do
  case $1 in
    --build) build=${2:?}; shift 2 ;;
    -n) n=${2:?}; shift 2 ;;
    --runs) runs=${2:?}; shift 2 ;;
    --batch) batch=${2:?}; shift 2 ;;
    --inside) inside=1; shift ;;
    *) sed -n '2,8s/^# \{0,1\}//p' "$0" >&2; exit 2 ;;
  esac
done
bin=$(cd "$build" 2>/dev/null && pwd)/bench/carril_can_throughput

if [ $inside -eq 0 ]; then
  [ -x "$bin" ] || { echo "bench_vcan: no $bin (cmake --build --preset host --target carril_can_throughput)" >&2; exit 2; }
  command -v cangen >/dev/null || { echo "bench_vcan: SKIP: no cangen (apt-get install can-utils)" >&2; exit 77; }
  exec "$here/uml_run.sh" --vcan 1 --timeout 600 -- bash "$here/bench_vcan.sh" --inside \
    --build "$build" -n "$n" --runs "$runs" --batch "$batch"
fi

# Inside the guest. Starting a process is slow under user-mode-linux (every system call of the
# dynamic loader traps to the host), and carril's binary loads libstdc++: each tool's start-up is
# timed with -n 1 and taken off, so the rates compare the send paths.
now_ns() { date +%s%N; }
time_ns() {  # runs "$@" quietly, prints its wall time [ns]
  local t0 t1
  t0=$(now_ns)
  "$@" >/dev/null || { echo "bench_vcan: failed: $*" >&2; exit 1; }
  t1=$(now_ns)
  echo $((t1 - t0))
}
rate() { awk -v n="$1" -v ns="$2" 'BEGIN { printf "%.0f", n / (ns / 1e9) }'; }
median() { printf '%s\n' "$@" | sort -n | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
echo "kernel $(uname -r) (user-mode-linux), vcan0, $n frames a run, $runs runs each, carril tx_batch $batch"
cg=() cr=() cgw=() crw=()
for ((r = 1; r <= runs; r++)); do
  c1=$(time_ns cangen vcan0 -g 0 -n 1)
  cn=$(time_ns cangen vcan0 -g 0 -n "$n")
  k1=$(time_ns "$bin" --iface vcan0 -n 1 --batch "$batch")
  kn=$(time_ns "$bin" --iface vcan0 -n "$n" --batch "$batch")
  cgw+=("$(rate "$n" "$cn")") crw+=("$(rate "$n" "$kn")")
  cg+=("$(rate $((n - 1)) $((cn - c1)))") cr+=("$(rate $((n - 1)) $((kn - k1)))")
  echo "run $r: cangen vcan0 -g 0 -n $n: $((cn / 1000000)) ms (start-up $((c1 / 1000000)) ms):" \
    "${cg[-1]} frames/s, ${cgw[-1]} with start-up"
  echo "run $r: carril_can_throughput -n $n --batch $batch: $((kn / 1000000)) ms (start-up $((k1 / 1000000)) ms):" \
    "${cr[-1]} frames/s, ${crw[-1]} with start-up"
done
mc=$(median "${cg[@]}") mr=$(median "${cr[@]}")
ratio=$(awk -v a="$mr" -v b="$mc" 'BEGIN { printf "%.2f", a / b }')
ratiow=$(awk -v a="$(median "${crw[@]}")" -v b="$(median "${cgw[@]}")" 'BEGIN { printf "%.2f", a / b }')
echo "median: cangen $mc frames/s, carril $mr frames/s, carril / cangen = $ratio (goal >= 1);" \
  "with start-up: $ratiow"
awk -v r="$ratio" 'BEGIN { exit !(r >= 1.0) }' || echo "bench_vcan: carril is below cangen's rate"
