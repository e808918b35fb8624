#!/usr/bin/env bash
# Runs inside user-mode-linux (tools/uml/hil_test.sh starts it): carril_sim --hil and
# carril_controller on vcan0, twice.
#   run A: the circle for LAP_S seconds (a lap), then drive 1's heartbeat goes silent
#          (--inject); candump captures vcan0 from 6 s before the silence to the end.
#   run B: the controller is killed with SIGKILL while the robot drives; both write --can-log
#          (the controller's stays FILE.part: it was killed before it could complete it).
# Every syscall traps to the host under user-mode-linux, so the capture is a window, not the run.
# Usage: hil_inside.sh SIM CONTROLLER SOURCE_DIR OUT_DIR LAP_S
set -uo pipefail
sim=$1 ctl=$2 src=$3 out=$4 lap_s=${5:-45}
cd "$src"
robot=config/robots/campero.yaml
controller=config/controller/campero_hil.yaml
mission=config/missions/follow_line.yaml
mkdir -p "$out"

# Waits until FILE contains PATTERN, at most S seconds; false when it does not.
wait_for() {
  local file=$1 pattern=$2 s=$3
  for ((i = 0; i < s * 10; i++)); do
    grep -q "$pattern" "$file" 2>/dev/null && return 0
    sleep 0.1
  done
  return 1
}

# Starts the simulator for run NAME (DURATION s, more options after) and waits for its banner.
start_sim() {
  local name=$1 duration=$2
  shift 2
  "$sim" --hil --can vcan0 --controller "$controller" --scenario scenarios/circle.yaml \
    --out "$out/$name" --duration "$duration" "$@" >"$out/$name.sim.txt" 2>&1 &
  simpid=$!
  sim_t0=$(date +%s.%N)
  wait_for "$out/$name.sim.txt" 'carril_sim: HIL:' 30 || echo "hil_inside: $name: no HIL banner" >&2
}

# Run A.
start_sim a "$((lap_s + 8))" --inject "$lap_s:1:heartbeat_silence"
"$ctl" --robot "$robot" --controller "$controller" --mission "$mission" >"$out/a.ctl.txt" 2>&1 &
ctlpid=$!
sleep "$(awk -v t0="$sim_t0" -v l="$lap_s" -v now="$(date +%s.%N)" 'BEGIN { s = t0 + l - 6 - now; print (s > 0 ? s : 0) }')"
candump -L vcan0 >"$out/a.candump" &
dump=$!
wait "$simpid"; echo "sim_a_exit $?" >>"$out/exits"
kill "$dump" 2>/dev/null; wait "$dump" 2>/dev/null
kill -INT "$ctlpid" 2>/dev/null; wait "$ctlpid"; echo "ctl_a_exit $?" >>"$out/exits"

# Run B: the controller dies (SIGKILL) while the robot follows the tape.
start_sim b 30 --can-log "$out/b.sim.canlog"
"$ctl" --robot "$robot" --controller "$controller" --mission "$mission" \
  --can-log "$out/b.ctl.canlog" >"$out/b.ctl.txt" 2>&1 &
ctlpid=$!
if wait_for "$out/b.ctl.txt" 'FOLLOW/track' 25; then
  sleep 4
  kill -KILL "$ctlpid"
  echo "killed_b" >>"$out/exits"
fi
wait "$ctlpid" 2>/dev/null; echo "ctl_b_exit $?" >>"$out/exits"
wait "$simpid"; echo "sim_b_exit $?" >>"$out/exits"
exit 0
