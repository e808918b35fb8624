#!/usr/bin/env bash
# carril_campaign's command-line contract with the real simulator: a small campaign runs, writes
# its CSV and a scenario per variant that replays byte for byte; a second run runs nothing; Ctrl-C
# stops it with exit 130 and a resume runs only what was left; bad input exits 2 naming the file
# and key; another campaign's folder is refused.
# Usage: campaign_cli_test.sh <carril_campaign> <carril_sim> <source dir>
set -u
campaign=$1
sim=$2
src=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
. "$(dirname "${BASH_SOURCE[0]}")/check.sh"
mkdir -p "$work/c"
cat >"$work/c/small.yaml" <<YAML
name: small
seed: 3
scenarios: [$src/scenarios/circle.yaml]
robots: [{preset: pioneer3at, strategy: pid}]
variants: 3
perturbations:
  start_offset_m: {uniform: [-0.02, 0.02]}
  camera_noise: {uniform: [0, 5]}
YAML
run() { "$campaign" run "$work/c/small.yaml" --sim "$sim" --out "$work/out" "$@"; }

# 1. A whole run: exit 0, three rows, a status and a scenario per variant.
run --jobs 2 >"$work/o1" 2>"$work/e1"
check "run exits 0" test $? -eq 0
check "run says it ran 3" grep -q "ran 3 variants now, 0 had finished before" "$work/o1"
check "results.csv has a header and 3 rows" test "$(wc -l <"$work/out/results.csv")" -eq 4
check "the CSV names the perturbations" grep -q "^index,base_scenario,preset,strategy,seed,start_offset_m,camera_noise,status," "$work/out/results.csv"
check "every variant has a status" test "$(cat "$work"/out/runs/*/status | grep -c '^exit [01]$')" -eq 3
check "the progress line went to stderr" grep -q "3/3 done" "$work/e1"
check "the report gives the pass rate" grep -q "^\*\*Pass rate: " "$work/out/report.md"
check "the report names a replay command" grep -q -- "--scenario $work/out/runs/000000/scenario.yaml --view" "$work/out/report.md"
check "the report's plots are PNGs" test "$(head -c 4 "$work/out/report/perturbation_camera_noise.png" | tail -c 3)" = PNG

# 2. The variant's scenario replays: same trajectory byte for byte.
"$sim" --scenario "$work/out/runs/000001/scenario.yaml" --out "$work/replay" --quiet >/dev/null
check "a variant replays byte for byte" cmp -s "$work/replay/trajectory.csv" "$work/out/runs/000001/sim/trajectory.csv"
check "variants differ" bash -c "! cmp -s '$work/out/runs/000000/sim/trajectory.csv' '$work/out/runs/000001/sim/trajectory.csv'"

# 3. Nothing finished runs twice.
run >"$work/o2" 2>&1
check "a second run exits 0" test $? -eq 0
check "a second run runs nothing" grep -q "ran 0 variants now, 3 had finished before" "$work/o2"
"$campaign" status "$work/c/small.yaml" --out "$work/out" >"$work/o3"
check "status counts 3 finished" grep -q "3 variants: 3 finished" "$work/o3"

# 4. Ctrl-C: exit 130, no status for the stopped variant, a resume runs only what is left.
rm -rf "$work/out"
# The binary itself in the background ($! of a function would be a subshell's).
"$campaign" run "$work/c/small.yaml" --sim "$sim" --out "$work/out" --jobs 1 --quiet >"$work/o4" 2>&1 &
pid=$!
for _ in $(seq 600); do
  [ -f "$work/out/runs/000000/status" ] && break
  sleep 0.05
done
kill -INT $pid
wait $pid
check "Ctrl-C exits 130" test $? -eq 130
check "Ctrl-C says how to resume" grep -q "run the same command again to resume" "$work/o4"
done_before=$(ls "$work"/out/runs/*/status 2>/dev/null | wc -l)
check "at least one variant finished before Ctrl-C, not all" test "$done_before" -ge 1 -a "$done_before" -lt 3
run --quiet >"$work/o5" 2>&1
check "the resume exits 0" test $? -eq 0
check "the resume runs only what was left" grep -q "ran $((3 - done_before)) variants now, $done_before had finished before" "$work/o5"
check "after the resume 3 rows" test "$(wc -l <"$work/out/results.csv")" -eq 4

# 5. Bad input: exit 2, the file and the key named.
sed 's/variants: 3/variants: 3\nruns: 2/' "$work/c/small.yaml" >"$work/c/bad.yaml"
"$campaign" run "$work/c/bad.yaml" --sim "$sim" --out "$work/bad" >/dev/null 2>"$work/e6"
check "an unknown key exits 2" test $? -eq 2
check "the message names the file and the key" grep -q "bad.yaml:[0-9]*: runs" "$work/e6"
sed 's/camera_noise: {uniform: \[0, 5\]}/camera_noise: {uniform: [5, 0]}/' "$work/c/small.yaml" >"$work/c/bad2.yaml"
"$campaign" run "$work/c/bad2.yaml" --sim "$sim" --out "$work/bad2" >/dev/null 2>"$work/e7"
check "an impossible distribution exits 2" test $? -eq 2
check "the message names the distribution" grep -q "perturbations.camera_noise.uniform" "$work/e7"
sed 's/seed: 3/seed: 4/' "$work/c/small.yaml" >"$work/c/other.yaml"
"$campaign" run "$work/c/other.yaml" --sim "$sim" --out "$work/out" >/dev/null 2>"$work/e8"
check "another campaign's folder exits 2" test $? -eq 2
check "the message says it holds another campaign" grep -q "another campaign" "$work/e8"

# 6. A cluster that refuses the job (a stand-in sbatch): exit 2 with what it said, nothing lost.
printf '#!/bin/sh\necho "sbatch: error: Batch job submission failed: Invalid account" >&2\nexit 1\n' >"$work/sbatch"
chmod +x "$work/sbatch"
rm -f "$work"/out/runs/000002/status  # as if its worker had died
"$campaign" run "$work/c/small.yaml" --sim "$sim" --out "$work/out" --slurm --sbatch "$work/sbatch" >/dev/null 2>"$work/e9"
check "a refused submission exits 2" test $? -eq 2
check "the message quotes the cluster" grep -q "refused the job (exit 1): sbatch: error: Batch job submission failed: Invalid account; nothing was submitted" "$work/e9"
"$campaign" status "$work/c/small.yaml" --out "$work/out" >"$work/o10"
check "the finished variants are kept" grep -q "3 variants: 2 finished" "$work/o10"
printf '#!/bin/sh\necho 4242\n' >"$work/sbatch"
"$campaign" run "$work/c/small.yaml" --sim "$sim" --out "$work/out" --slurm --sbatch "$work/sbatch" --chunk-size 2 >"$work/o11" 2>&1
check "only the chunk with an unfinished variant is submitted" grep -q "^#SBATCH --array=1$" "$work/out/slurm/job.sh"
check "the job id is kept" grep -q "^4242$" "$work/out/slurm/job_id"

echo "campaign_cli_test: $passes passed, $fails failed"
[ "$fails" -eq 0 ]
