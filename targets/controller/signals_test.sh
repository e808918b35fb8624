#!/usr/bin/env bash
# carril_controller under every stopping signal and with its stdout closed (issue 46 item 6): on
# the bench (no CAN bus, null drives), SIGINT, SIGTERM and SIGHUP each end the loop with the
# report that names the signal and exit 1 (stopped before the requested ticks); with stdout a
# pipe whose reader has gone, the controller is not killed by SIGPIPE and still stops on SIGTERM.
# Usage: signals_test.sh CONTROLLER SOURCE_DIR [EMULATOR...]
set -uo pipefail
ctl=$1 src=$2
shift 2
emu=("$@")
work=$(mktemp -d "${TMPDIR:-/tmp}/carril_signals.XXXXXX")
trap 'rm -rf "$work"' EXIT
args=(--robot "$src/config/robots/campero.yaml" --controller "$src/config/controller/bench.yaml"
  --mission "$src/config/missions/follow_line.yaml" --ticks 1000000)
fail=0

# Waits until FILE contains PATTERN, at most S seconds (a loaded machine: generous).
wait_for() {
  local file=$1 pattern=$2 s=$3
  for ((i = 0; i < s * 10; i++)); do
    grep -q "$pattern" "$file" 2>/dev/null && return 0
    sleep 0.1
  done
  return 1
}

for sig in INT TERM HUP; do
  out="$work/$sig.txt"
  "${emu[@]}" "$ctl" "${args[@]}" >"$out" 2>&1 &
  pid=$!
  if ! wait_for "$out" 'running' 60; then
    echo "signals_test: SIG$sig: the controller did not start"; fail=1
  fi
  sleep 0.5
  kill -"$sig" "$pid"
  wait "$pid"
  rc=$?
  if [ "$rc" -ne 1 ]; then
    echo "signals_test: SIG$sig: exit $rc, expected 1 (stopped by the signal, report printed)"
    fail=1
  fi
  if ! grep -q "stopped by a signal (SIG$sig) after [0-9]* of 1000000 ticks" "$out"; then
    echo "signals_test: SIG$sig: no report naming the signal"; fail=1
  fi
  grep -q "loop: periods" "$out" || { echo "signals_test: SIG$sig: no loop figures"; fail=1; }
done

# stdout into a FIFO whose reader takes one byte and leaves: every later write is EPIPE.
fifo="$work/out.fifo"
mkfifo "$fifo"
head -c 1 "$fifo" >/dev/null &
reader=$!
"${emu[@]}" "$ctl" "${args[@]}" >"$fifo" 2>"$work/pipe.err" &
pid=$!
wait "$reader"
# The status lines of the slow rate group go on being written (5 Hz) into the closed pipe.
sleep 3
if ! kill -0 "$pid" 2>/dev/null; then
  wait "$pid"
  echo "signals_test: closed stdout: the controller died (exit $?) before any signal"
  fail=1
else
  kill -TERM "$pid"
  wait "$pid"
  rc=$?
  [ "$rc" -eq 1 ] || { echo "signals_test: closed stdout: exit $rc after SIGTERM, expected 1"; fail=1; }
fi
[ $fail -eq 0 ] && echo "signals_test: SIGINT, SIGTERM, SIGHUP stop with the report; a closed stdout does not kill"
exit $fail
