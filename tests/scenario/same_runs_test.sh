#!/bin/bash
# The fast simulator (tools/build_fast_sim.sh: profile-guided and link-time optimised) runs a
# scenario exactly as the host build does: the same trajectory.csv to the byte and the same
# summary.json apart from what measures the host's clock (wall time, real-time factor, tick and
# task compute times and the overruns they cause).
# Usage: same_runs_test.sh FAST_SIM REFERENCE_SIM SCENARIO.yaml
fast=$1 ref=$2 scn=$3
work=$(mktemp -d) || exit 1
trap 'rm -rf "$work"' EXIT
for which in fast ref; do
  sim=$fast
  [ "$which" = ref ] && sim=$ref
  "$sim" --scenario "$scn" --out "$work/$which" --quiet --no-plots >/dev/null 2>&1
  rc=$?
  # 0 and 1 are a run's verdicts; anything else is an error.
  if [ "$rc" -gt 1 ] || [ ! -s "$work/$which/summary.json" ]; then
    echo "FAIL: $scn: the $which simulator ended with $rc and no summary"
    exit 1
  fi
done
timing='"(wall_time_s|real_time_factor|tick_compute_[a-z0-9_]+|tick_overruns|task_overrun_events|tasks)":'
if ! cmp "$work/fast/trajectory.csv" "$work/ref/trajectory.csv"; then
  echo "FAIL: $scn: trajectory.csv differs"
  exit 1
fi
if ! diff <(grep -v -E "$timing" "$work/fast/summary.json") \
  <(grep -v -E "$timing" "$work/ref/summary.json"); then
  echo "FAIL: $scn: summary.json differs beyond the timing fields"
  exit 1
fi
echo "$scn: $(wc -l <"$work/fast/trajectory.csv") trajectory rows and the summary equal"
