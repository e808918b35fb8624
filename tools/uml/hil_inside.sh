#!/usr/bin/env bash
# Runs inside user-mode-linux (tools/uml/hil_test.sh starts it): carril_sim --hil and
# carril_controller on vcan0, twice, capturing every frame with candump.
#   run A: the circle for one lap, then drive 1's heartbeat goes silent (--inject);
#   run B: the controller is killed with SIGKILL while the robot drives.
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

# Starts candump, the simulator and the controller for run NAME; sets dump, simpid, ctlpid.
run() {
  local name=$1 duration=$2
  shift 2
  candump -L vcan0 >"$out/$name.candump" &
  dump=$!
  "$sim" --hil --can vcan0 --controller "$controller" --scenario scenarios/circle.yaml \
    --out "$out/$name" --duration "$duration" --can-log "$out/$name.simlog" "$@" \
    >"$out/$name.sim.txt" 2>&1 &
  simpid=$!
  wait_for "$out/$name.sim.txt" 'carril_sim: HIL:' 30 || echo "hil_inside: $name: no HIL banner" >&2
  "$ctl" --robot "$robot" --controller "$controller" --mission "$mission" \
    >"$out/$name.ctl.txt" 2>&1 &
  ctlpid=$!
}

# Run A: a lap, then drive 1 drops its heartbeat.
run a "$((lap_s + 8))" --inject "$lap_s:1:heartbeat_silence"
wait "$simpid"; echo "sim_a_exit $?" >>"$out/exits"
kill -INT "$ctlpid" 2>/dev/null; wait "$ctlpid"; echo "ctl_a_exit $?" >>"$out/exits"
kill "$dump" 2>/dev/null; wait "$dump" 2>/dev/null

# Run B: the controller dies (SIGKILL) while the robot follows the tape.
run b 30
if wait_for "$out/b.ctl.txt" 'FOLLOW/track' 25; then
  sleep 4
  kill -KILL "$ctlpid"
  echo "killed_b $(awk '{print $1}' /proc/uptime)" >>"$out/exits"
fi
wait "$ctlpid" 2>/dev/null; echo "ctl_b_exit $?" >>"$out/exits"
wait "$simpid"; echo "sim_b_exit $?" >>"$out/exits"
kill "$dump" 2>/dev/null; wait "$dump" 2>/dev/null
exit 0
