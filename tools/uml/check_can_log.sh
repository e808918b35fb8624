#!/usr/bin/env bash
# Checks that can-utils reads carril's candump log (CanLogTap): carril_can_loopback_sustain
# writes a log of a short run on the host, then inside user-mode-linux canplayer replays it onto
# vcan0 while candump -L records vcan0, and the two logs must hold the same frames in the same
# order. Exit 77 when user-mode-linux cannot start.
# Usage: tools/uml/check_can_log.sh PATH/TO/carril_can_loopback_sustain
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)

if [ "${1:-}" = --inside ]; then
  dir=$2
  # A big receive buffer: under user-mode-linux candump is slow to read and would drop frames.
  candump -r 8000000 -L vcan0 >"$dir/replayed.log" &
  dump=$!
  sleep 0.5  # candump's socket is bound
  canplayer -I "$dir/carril.log" || { echo "check_can_log: canplayer refused the log" >&2; exit 1; }
  sleep 0.5
  kill "$dump"
  wait "$dump" 2>/dev/null
  exit 0
fi

sustain=${1:?usage: check_can_log.sh PATH/TO/carril_can_loopback_sustain}
for t in canplayer candump; do
  command -v $t >/dev/null || { echo "check_can_log: SKIP: no $t (apt-get install can-utils)" >&2; exit 77; }
done
dir=$(mktemp -d "${TMPDIR:-/tmp}/check_can_log.XXXXXX")
trap 'rm -rf "$dir"' EXIT
"$sustain" --seconds 0.2 --log "$dir/carril.log" || exit 1
"$here/uml_run.sh" --vcan 1 --timeout 240 -- bash "$here/check_can_log.sh" --inside "$dir"
rc=$?
[ $rc -eq 0 ] || exit $rc
# Frames only: the timestamps differ (candump stamps the replay).
frames() { awk '{ print $2, $3 }' "$1"; }
n=$(wc -l <"$dir/carril.log")
m=$(wc -l <"$dir/replayed.log")
if ! diff <(frames "$dir/carril.log") <(frames "$dir/replayed.log") >"$dir/diff"; then
  echo "check_can_log: canplayer replayed $m of $n frames differently; first differences:" >&2
  head -n 10 "$dir/diff" >&2
  exit 1
fi
echo "check_can_log: canplayer replayed all $n frames of carril's log onto vcan0, candump saw them unchanged"
