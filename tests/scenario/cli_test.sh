#!/usr/bin/env bash
# carril_sim's command-line contract: exit codes 0/1/2, error messages, output files, Ctrl-C.
# Usage: cli_test.sh <carril_sim> <source dir>
set -u
sim=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fails=0
passes=0
check() {  # check <description> <condition...>
  local what=$1
  shift
  if "$@"; then
    passes=$((passes + 1))
  else
    echo "FAIL: $what"
    fails=$((fails + 1))
  fi
}

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
check "no temporary files left" test -z "$(ls "$work/circle" | grep -v -E '^(trajectory.csv|summary.json|trajectory.png|velocities.png)$')"

# 6. --seed overrides the scenario's seed and is reproducible.
"$sim" --scenario "$src/scenarios/circle.yaml" --out "$work/s1" --seed 5 --quiet >/dev/null 2>&1
"$sim" --scenario "$src/scenarios/circle.yaml" --out "$work/s2" --seed 5 --quiet >/dev/null 2>&1
check "same seed, same trajectory file" cmp -s "$work/s1/trajectory.csv" "$work/s2/trajectory.csv"

# 7. Ctrl-C during a --realtime run: stops, still writes everything, result "aborted", exit 1.
"$sim" --scenario "$src/scenarios/square.yaml" --out "$work/int" --realtime >"$work/out" 2>"$work/err" &
pid=$!
sleep 2
kill -INT "$pid"
wait "$pid"
rc=$?
check "interrupted run exits 1" test $rc -eq 1
check "interrupted run wrote summary" grep -q '"result": "aborted"' "$work/int/summary.json"
rows=$(($(wc -l <"$work/int/trajectory.csv") - 1))
check "interrupted run kept its rows (got $rows)" test "$rows" -ge 100
check "interrupted run took about real time" python3 -c "import json,sys; s=json.load(open('$work/int/summary.json')); sys.exit(0 if 1.0 < s['sim_time_s'] < 4.0 else 1)"

# 8. --view without a display is a usage error, not a crash.
env -u DISPLAY "$sim" --scenario "$src/scenarios/circle.yaml" --out "$work/view" --view >"$work/out" 2>"$work/err"
check "--view without display exits 2" test $? -eq 2
check "--view says why" grep -q "no display" "$work/err"

echo "cli: $passes passed, $fails failed"
test "$fails" -eq 0
