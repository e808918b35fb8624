#!/usr/bin/env bash
# carril_sim's command-line contract: exit codes 0/1/2, error messages, output files, --seed and
# --out checks, signals (Ctrl-C, SIGHUP, SIGTERM in start-up).
# Usage: cli_test.sh <carril_sim> <source dir>
set -u
sim=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
. "$(dirname "${BASH_SOURCE[0]}")/check.sh"

differ() { ! cmp -s "$1" "$2"; }

# 1. Usage error: no --scenario.
"$sim" >"$work/out" 2>"$work/err"
check "no --scenario exits 2" test $? -eq 2

# 2. Bad input: unknown key, message names the file and the key path.
sed 's/^  line_color: white/  line_colour: white/' "$src/scenarios/circle.yaml" >"$work/bad.yaml"
"$sim" --scenario "$work/bad.yaml" --out "$work/bad" >"$work/out" 2>"$work/err"
check "unknown key exits 2" test $? -eq 2
check "error names the file" grep -q "bad.yaml" "$work/err"
check "error names the key path" grep -q "mission.line_colour" "$work/err"
check "nothing written on bad input" test ! -e "$work/bad"

# 3. Missing file.
"$sim" --scenario "$work/nope.yaml" >"$work/out" 2>"$work/err"
check "missing file exits 2" test $? -eq 2
check "missing file named" grep -q "nope.yaml" "$work/err"

# 3b. A coverage area with no free cell the robot fits in (a triangle inside a wall of the house):
# exit 2 naming mission.area, before any run.
cat >"$work/no_area.yaml" <<EOF
name: no_area
duration_s: 10
map: $src/scenarios/maps/house.yaml
robot: {preset: pioneer3at, start: {x: 0.0, y: 0.0, yaw_deg: 0.0}}
mission: {type: coverage, mode: systematic, area: [[1.9, 0.71], [2.1, 0.71], [2.0, 0.79]]}
EOF
"$sim" --scenario "$work/no_area.yaml" --out "$work/no_area" >"$work/out" 2>"$work/err"
check "coverage area without a free cell exits 2" test $? -eq 2
check "coverage area without a free cell: named" grep -q "no_area.yaml: mission.area: coverage area: no free cell where the robot fits" "$work/err"
check "coverage area without a free cell: nothing written" test ! -e "$work/no_area"

# 4. A run that misses its expect block exits 1 and says which expectation.
sed 's/^duration_s: 50/duration_s: 5/' "$src/scenarios/circle.yaml" >"$work/short.yaml"
"$sim" --scenario "$work/short.yaml" --out "$work/short" >"$work/out" 2>"$work/err"
check "unmet expectation exits 1" test $? -eq 1
check "unmet expectation reported" grep -q "unmet: min_progress" "$work/out"

# 5. A passing run exits 0 and writes the four files whole.
"$sim" --scenario "$src/scenarios/circle.yaml" --out "$work/circle" --quiet >"$work/out" 2>"$work/err"
check "circle exits 0" test $? -eq 0
for f in trajectory.csv summary.json trajectory.png velocities.png; do
  check "circle wrote $f" test -s "$work/circle/$f"
done
check "csv header" test "$(head -1 "$work/circle/trajectory.csv")" = "t,x,y,yaw,vx,vy,wz,state,cross_track_m"
check "summary says passed" grep -q '"passed": true' "$work/circle/summary.json"
# A robot with a lidar builds a costmap: its images and the map_server pair join the set.
check "no temporary files left" test -z "$(ls "$work/circle" | grep -v -E '^(trajectory.csv|summary.json|trajectory.png|velocities.png|costmap.png|costmap.pgm|costmap.yaml|obstacles.png)$')"

# 6. --seed overrides the scenario's seed and is reproducible. The circle with camera and lidar
# noise (the plain circle has none, so there every seed gives the same file) and a short run:
# the same seed gives the same trajectory, and, as the control, another seed a different one.
sed -e 's/^duration_s: 50/duration_s: 8/' \
  -e 's/^  start: \(.*\)$/  start: \1\n  camera: {noise_std: 40}\n  lidar: {noise_std_m: 0.02}/' \
  "$src/scenarios/circle.yaml" >"$work/noisy.yaml"
check "noisy copy has the camera override" grep -q "^  camera: {noise_std: 40}" "$work/noisy.yaml"
check "noisy copy has the lidar override" grep -q "^  lidar: {noise_std_m: 0.02}" "$work/noisy.yaml"
for run in s1:5 s2:5 s3:6; do
  "$sim" --scenario "$work/noisy.yaml" --out "$work/${run%%:*}" --seed "${run#*:}" --quiet >/dev/null 2>&1
  check "noisy run ${run%%:*} ran to its time limit (exit 1, unmet laps)" test $? -eq 1
  check "noisy run ${run%%:*} wrote its trajectory" test -s "$work/${run%%:*}/trajectory.csv"
done
check "same seed, same trajectory file" cmp -s "$work/s1/trajectory.csv" "$work/s2/trajectory.csv"
check "different seed, different trajectory file" differ "$work/s1/trajectory.csv" "$work/s3/trajectory.csv"

# 7. Ctrl-C (SIGINT) or a hang-up (SIGHUP) during a --realtime run: stops, still writes
# everything, result "aborted", exit 1.
for sig in INT HUP; do
  "$sim" --scenario "$src/scenarios/square.yaml" --out "$work/int_$sig" --realtime >"$work/out" 2>"$work/err" &
  pid=$!
  # 3 s of wall time: the run is at least 1 s in even when start-up is slow on a loaded host.
  sleep 3
  kill -"$sig" "$pid"
  wait "$pid"
  rc=$?
  d="$work/int_$sig"
  check "SIG$sig: interrupted run exits 1" test $rc -eq 1
  check "SIG$sig: interrupted run wrote summary" grep -q '"result": "aborted"' "$d/summary.json"
  rows=$(($(wc -l <"$d/trajectory.csv") - 1))
  check "SIG$sig: interrupted run kept its rows (got $rows)" test "$rows" -ge 100
  check "SIG$sig: interrupted run took about real time" python3 -c "import json,sys; s=json.load(open('$d/summary.json')); sys.exit(0 if 1.0 < s['sim_time_s'] < 4.0 else 1)"
done

# 8. --view without a display is a usage error, not a crash.
env -u DISPLAY "$sim" --scenario "$src/scenarios/circle.yaml" --out "$work/view" --view >"$work/out" 2>"$work/err"
check "--view without display exits 2" test $? -eq 2
check "--view says why" grep -q "no display" "$work/err"

# 8b. The window lives in libcarril_sim_window.so, loaded only for --view: carril_sim itself
# loads no GUI toolkit (which made every start 0.2 s instead of 0.02 s).
check "carril_sim is not linked to highgui or Qt" bash -c "! ldd '$sim' | grep -qiE 'highgui|Qt5'"
# Qt's offscreen platform stands in for a display: the view opens, draws every frame and closes.
QT_QPA_PLATFORM=offscreen DISPLAY=:99 timeout 120 "$sim" --scenario "$work/short.yaml" \
  --out "$work/viewed" --view --quiet >"$work/out" 2>"$work/err"
status=$?
check "--view on an offscreen display runs the scenario to its end" \
  bash -c "[ $status -le 1 ] && grep -q '\"sim_time_s\": 5' '$work/viewed/summary.json'"
# Without the module beside it, --view is refused and names the file.
mkdir -p "$work/lonely" && cp "$sim" "$work/lonely/carril_sim"
DISPLAY=:99 "$work/lonely/carril_sim" --scenario "$work/short.yaml" --out "$work/lonely/o" --view \
  >"$work/out" 2>"$work/err"
check "--view without the window module exits 2" test $? -eq 2
check "--view names the missing module" grep -q "libcarril_sim_window.so" "$work/err"

# 9. --seed follows the scenario file's rule for `seed`: digits, an optional leading '+', at most
# 2^64 - 1. Everything else is a usage error that names --seed, before the run starts.
for bad in -1 18446744073709551616 1.5 1e3 "" abc 0x10 " 5" 5x; do
  rm -rf "$work/seed"
  "$sim" --scenario "$work/short.yaml" --out "$work/seed" --seed="$bad" >"$work/out" 2>"$work/err"
  check "--seed '$bad' exits 2" test $? -eq 2
  check "--seed '$bad': message names --seed and what it expects" grep -q -- "--seed: expected an integer in \[0, 18446744073709551615\]" "$work/err"
  check "--seed '$bad': the run did not start" test ! -s "$work/out" -a ! -e "$work/seed"
done
"$sim" --scenario "$work/short.yaml" --out "$work/seed" --seed -1 >"$work/out" 2>"$work/err"
check "--seed -1 (separate argument) exits 2" test $? -eq 2
check "--seed -1 names --seed" grep -q -- "--seed: expected" "$work/err"
"$sim" --scenario "$work/short.yaml" --out "$work/seed" --seed >"$work/out" 2>"$work/err"
check "--seed without a value exits 2" test $? -eq 2
check "--seed without a value names --seed" grep -q -- "--seed: expected" "$work/err"
for good in +7:7 18446744073709551615:18446744073709551615 007:7; do
  "$sim" --scenario "$work/short.yaml" --out "$work/seed" --seed "${good%%:*}" >"$work/out" 2>"$work/err"
  check "--seed ${good%%:*} accepted (exit 1: the short run misses its laps)" test $? -eq 1
  check "--seed ${good%%:*} is seed ${good#*:}" grep -q "seed ${good#*:}, " "$work/out"
done

# 10. --out is checked before the run: a path that cannot be created, or a directory holding other
# files (the whole directory is replaced), is exit 2 with the path and the reason, and no run.
: >"$work/plainfile"
start=$(date +%s%N)
"$sim" --scenario "$src/scenarios/circle.yaml" --out "$work/plainfile/run" >"$work/out" 2>"$work/err"
rc=$?
ms=$((($(date +%s%N) - start) / 1000000))
check "--out under a regular file exits 2" test $rc -eq 2
check "--out error names the path and the reason" grep -q -- "--out: .*plainfile/run.*Not a directory" "$work/err"
check "--out error comes before any run output" test ! -s "$work/out"
check "--out error is immediate (took ${ms} ms)" test "$ms" -lt 2000
if [ "$(id -u)" -ne 0 ]; then  # root writes anywhere
  mkdir "$work/ro" && chmod a-w "$work/ro"
  "$sim" --scenario "$src/scenarios/circle.yaml" --out "$work/ro/sub/run" >"$work/out" 2>"$work/err"
  check "--out under a read-only directory exits 2" test $? -eq 2
  check "--out read-only: path and reason" grep -q -- "--out: .*ro/sub.*Permission denied" "$work/err"
  check "--out read-only: no run" test ! -s "$work/out"
  chmod u+w "$work/ro"
fi
mkdir -p "$work/mine"
echo "my notes" >"$work/mine/notes.txt"
"$sim" --scenario "$src/scenarios/circle.yaml" --out "$work/mine" >"$work/out" 2>"$work/err"
check "--out with foreign files exits 2" test $? -eq 2
check "--out foreign files: message names the file" grep -q -- "--out: .*mine.*notes.txt" "$work/err"
check "--out foreign files: no run" test ! -s "$work/out"
check "--out foreign files: the file is untouched" test "$(cat "$work/mine/notes.txt")" = "my notes"
# A previous run's directory is replaced as one set, with nothing left beside it.
"$sim" --scenario "$work/short.yaml" --out "$work/circle" --quiet >/dev/null 2>&1
check "rerun into a previous run's directory exits 1 (short run)" test $? -eq 1
check "rerun replaced the summary" grep -q '"result": "time_limit"' "$work/circle/summary.json"
check "rerun replaced the trajectory" test "$(wc -l <"$work/circle/trajectory.csv")" -lt 1000
check "rerun left exactly the run's files" test "$(ls -A "$work/circle" | sort | tr '\n' ' ')" = "costmap.pgm costmap.png costmap.yaml obstacles.png summary.json trajectory.csv trajectory.png velocities.png "
check "rerun left no staging directory" test -z "$(ls -A "$work" | grep '^\.')"

# 11. A signal during start-up (held there by the CARRIL_SIM_STARTUP_DELAY_MS test hook) stops
# carril_sim with a message naming the signal and the stage; exit 1, nothing written.
for sig in TERM INT HUP; do
  CARRIL_SIM_STARTUP_DELAY_MS=20000 "$sim" --scenario "$src/scenarios/circle.yaml" --out "$work/early_$sig" >"$work/out" 2>"$work/err" &
  pid=$!
  # Signal only once carril_sim catches it (its handler is installed first thing): on a loaded
  # machine a fixed sleep could strike before that and the default action would kill it.
  signo=$(kill -l "$sig")
  for _ in $(seq 1 200); do
    caught=$(awk '/^SigCgt:/ {print $2}' "/proc/$pid/status" 2>/dev/null)
    if [ -n "$caught" ] && (( (16#$caught >> (signo - 1)) & 1 )); then break; fi
    sleep 0.05
  done
  sleep 0.2
  start=$(date +%s%N)
  kill -"$sig" "$pid"
  wait "$pid"
  rc=$?
  ms=$((($(date +%s%N) - start) / 1000000))
  check "SIG$sig in start-up exits 1" test $rc -eq 1
  check "SIG$sig in start-up says so" grep -q "carril_sim: stopped by SIG$sig during start-up (loading the scenario); nothing written" "$work/err"
  check "SIG$sig in start-up wrote nothing" test ! -e "$work/early_$sig"
  check "SIG$sig in start-up ran no simulation" test ! -s "$work/out"
  check "SIG$sig in start-up stopped at once (took ${ms} ms)" test "$ms" -lt 5000
done

echo "cli: $passes passed, $fails failed"
test "$fails" -eq 0
