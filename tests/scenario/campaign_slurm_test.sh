#!/usr/bin/env bash
# carril_campaign on a real Slurm: brings up munge and a single-node Slurm on localhost in a
# temporary folder (its own key, sockets, ports and state; nothing of the machine's own
# configuration is used), runs a small campaign as a job array, and checks that its results are
# the local run's; a cancelled job's unfinished variants resume locally; a job the cluster
# refuses (an unknown partition) leaves the campaign as it was. Exits 77 (CTest: skipped), saying
# why, only where Slurm cannot be started at all.
# Usage: campaign_slurm_test.sh <carril_campaign> <carril_sim> <source dir>
set -u
campaign=$(realpath "$1")
sim=$(realpath "$2")
src=$3
work=$(mktemp -d)
cleanup() {
  [ -f "$work/slurmd.pid" ] && kill "$(cat "$work/slurmd.pid")" 2>/dev/null
  [ -f "$work/slurmctld.pid" ] && kill "$(cat "$work/slurmctld.pid")" 2>/dev/null
  [ -f "$work/munge/pid" ] && kill "$(cat "$work/munge/pid")" 2>/dev/null
  sleep 0.5
  rm -rf "$work"
}
trap cleanup EXIT
skip() {
  echo "SKIP: $1"
  for f in "$work"/log/* "$work"/munge/log; do
    [ -f "$f" ] && { echo "--- $f"; tail -n 5 "$f"; }
  done
  exit 77
}
. "$(dirname "${BASH_SOURCE[0]}")/check.sh"
for tool in munged slurmctld slurmd sbatch squeue sinfo scancel; do
  command -v "$tool" >/dev/null || skip "$tool is not installed (tools/setup.sh installs slurm-wlm and munge)"
done

# --- munge and Slurm, private to this test
mkdir -p "$work/munge" "$work/state" "$work/spool" "$work/log"
dd if=/dev/urandom of="$work/munge/key" bs=1024 count=1 2>/dev/null
chmod 400 "$work/munge/key"
force=()
[ "$(id -u)" -eq 0 ] && force=(--force)  # munged refuses root without it
munged "${force[@]}" --key-file="$work/munge/key" --socket="$work/munge/sock" \
  --pid-file="$work/munge/pid" --log-file="$work/munge/log" --seed-file="$work/munge/seed" ||
  skip "munged did not start"
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
host=$(hostname -s)
user=$(id -un)
cat >"$work/slurm.conf" <<CONF
ClusterName=carriltest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
AuthType=auth/munge
AuthInfo=socket=$work/munge/sock
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=1000 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf
slurmctld -f "$SLURM_CONF" || skip "slurmctld did not start"
slurmd -f "$SLURM_CONF" || skip "slurmd did not start"
state=""
for _ in $(seq 60); do
  state=$(sinfo -h -o %T 2>/dev/null)
  [ "$state" = idle ] && break
  sleep 0.5
done
[ "$state" = idle ] || skip "the Slurm node did not come up (state '$state')"

# --- a small campaign, locally and on Slurm
cat >"$work/small.yaml" <<YAML
name: slurm_small
seed: 21
scenarios: [$src/scenarios/circle.yaml]
robots: [{preset: pioneer3at, strategy: pid}, {preset: campero, strategy: marks}]
variants: 2
perturbations:
  start_offset_m: {uniform: [-0.02, 0.02]}
  wheel_slip: {uniform: [0, 0.02]}
YAML
# The columns that say what happened (not how long it took on which machine).
same_results() {
  python3 - "$1" "$2" <<'PY'
import csv, sys
keys = ['index', 'seed', 'start_offset_m', 'wheel_slip', 'status', 'result', 'passed',
        'sim_time_s', 'collisions', 'progress', 'laps', 'cross_track_rms_m',
        'cross_track_max_m', 'path_length_m', 'final_state']
rows = [[[r[k] for k in keys] for r in csv.DictReader(open(p))] for p in sys.argv[1:3]]
sys.exit(0 if rows[0] == rows[1] and len(rows[0]) == 4 else 1)
PY
}
wait_finished() {  # wait_finished <out> <count>
  for _ in $(seq 600); do
    "$campaign" status "$work/small.yaml" --out "$1" | grep -q "variants: $2 finished" && return 0
    sleep 0.5
  done
  return 1
}
"$campaign" run "$work/small.yaml" --sim "$sim" --out "$work/local" --quiet >"$work/o_local" 2>&1
check "the local run exits 0" test $? -eq 0

"$campaign" run "$work/small.yaml" --sim "$sim" --out "$work/slurm" --slurm --chunk-size 3 >"$work/o1" 2>&1
check "--slurm exits 0" test $? -eq 0
check "--slurm submits 2 array tasks" grep -q "submitted slurm job [0-9]*: 2 array tasks of up to 3 variants" "$work/o1"
check "the job script names the array" grep -q "^#SBATCH --array=0-1$" "$work/slurm/slurm/job.sh"
"$campaign" status "$work/small.yaml" --out "$work/slurm" >"$work/o2"
check "status names the slurm job" grep -q "slurm job [0-9]*:" "$work/o2"
check "the array finishes" wait_finished "$work/slurm" 4
"$campaign" collect "$work/small.yaml" --sim "$sim" --out "$work/slurm" >"$work/o3" 2>&1
check "collect exits 0" test $? -eq 0
check "the Slurm results are the local run's" same_results "$work/local/results.csv" "$work/slurm/results.csv"
"$campaign" run "$work/small.yaml" --sim "$sim" --out "$work/slurm" --slurm >"$work/o4" 2>&1
check "nothing left: nothing submitted" grep -q "nothing to submit" "$work/o4"

# --- a cancelled job (a worker dying mid-run) resumes locally
"$campaign" run "$work/small.yaml" --sim "$sim" --out "$work/cancel" --slurm --chunk-size 4 >"$work/o5" 2>&1
job=$(cat "$work/cancel/slurm/job_id" 2>/dev/null)
for _ in $(seq 600); do
  [ -n "$(ls "$work"/cancel/runs/*/status 2>/dev/null)" ] && break
  sleep 0.1
done
scancel "$job"
for _ in $(seq 100); do
  [ -z "$(squeue -h -j "$job" 2>/dev/null)" ] && break
  sleep 0.2
done
done_before=$(ls "$work"/cancel/runs/*/status 2>/dev/null | wc -l)
check "the cancelled job finished some variants, not all" test "$done_before" -ge 1 -a "$done_before" -lt 4
"$campaign" run "$work/small.yaml" --sim "$sim" --out "$work/cancel" --quiet >"$work/o6" 2>&1
check "the local resume runs only what the job left" grep -q "ran $((4 - done_before)) variants now, $done_before had finished before" "$work/o6"
check "the resumed results are the local run's" same_results "$work/local/results.csv" "$work/cancel/results.csv"

# --- a job the cluster refuses
rm -rf "$work/refused"
"$campaign" run "$work/small.yaml" --sim "$sim" --out "$work/refused" --slurm --partition no_such_partition >"$work/o7" 2>"$work/e7"
check "a refused job exits 2" test $? -eq 2
check "the message says sbatch refused it and why" grep -q "sbatch refused the job (exit 1): .*[Pp]artition" "$work/e7"
"$campaign" status "$work/small.yaml" --out "$work/refused" >"$work/o8"
check "the refused campaign is intact, nothing finished" grep -q "4 variants: 0 finished" "$work/o8"

echo "campaign_slurm_test: $passes passed, $fails failed"
[ "$fails" -eq 0 ]
