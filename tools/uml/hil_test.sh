#!/usr/bin/env bash
# The hardware-in-the-loop test (issue 9 item 8): boots user-mode-linux with vcan0, runs
# carril_sim --hil and carril_controller there (tools/uml/hil_inside.sh), then checks the capture
# (tools/uml/hil_check.py). Exit 77 (skip) only when user-mode-linux cannot start at all.
# Usage: [CARRIL_HIL_LOAD=N] [CARRIL_HIL_KEEP=1] hil_test.sh SIM CONTROLLER [LAP_S]
set -uo pipefail
sim=$1 ctl=$2 lap_s=${3:-45}
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
out=$(mktemp -d "${TMPDIR:-/tmp}/carril_hil.XXXXXX")
# CARRIL_HIL_LOAD=N: N busy processes load the host's cores for the whole run (issue 46 item 10:
# the HIL tests must pass on a loaded machine). They die with this script.
load_pids=()
for ((k = 0; k < ${CARRIL_HIL_LOAD:-0}; k++)); do
  bash -c 'while :; do :; done' &
  load_pids+=($!)
done
[ ${#load_pids[@]} -gt 0 ] && echo "hil_test: ${#load_pids[@]} busy processes load the host"
# CARRIL_HIL_KEEP=1 keeps the run's folder (captures, logs, summaries) and prints its path.
finish() {
  [ ${#load_pids[@]} -gt 0 ] && kill "${load_pids[@]}" 2>/dev/null
  if [ "${CARRIL_HIL_KEEP:-0}" = 1 ]; then echo "hil_test: kept $out"; else rm -rf "$out"; fi
}
trap finish EXIT
bash "$here/uml_run.sh" --vcan 1 --timeout 300 -- bash "$here/hil_inside.sh" "$sim" "$ctl" "$src" \
  "$out" "$lap_s"
rc=$?
[ $rc -eq 77 ] && exit 77
if [ $rc -ne 0 ]; then
  echo "hil_test: the run inside user-mode-linux failed (exit $rc)" >&2
fi
hb_ms=$(sed -nE 's/^ *drive_heartbeat_ms: *([0-9]+).*/\1/p' "$src/config/controller/campero_hil.yaml")
python3 "$here/hil_check.py" "$out" "$hb_ms"
check=$?
if [ $check -ne 0 ] || [ $rc -ne 0 ]; then
  for f in "$out"/*.txt; do echo "== $f (tail)"; tail -n 15 "$f"; done
  exit 1
fi
exit 0
