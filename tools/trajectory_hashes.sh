#!/usr/bin/env bash
# Prints "scenario seed sha256-of-trajectory.csv" for every shipped scenario at
# the given seeds, so two builds can be compared byte for byte (issue 47 item 8).
# Usage: tools/trajectory_hashes.sh CARRIL_SIM OUT_DIR [SEED...]   (default seeds 1 2 3 4)
set -euo pipefail
sim=${1:?usage: trajectory_hashes.sh CARRIL_SIM OUT_DIR [SEED...]}
out=${2:?usage: trajectory_hashes.sh CARRIL_SIM OUT_DIR [SEED...]}
shift 2
seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(1 2 3 4)
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
jobs=()
for f in "$here"/scenarios/*.yaml; do
  for s in "${seeds[@]}"; do jobs+=("$f $s"); done
done
run_one() {
  f=$1 s=$2 sim=$3 out=$4
  name=$(basename "$f" .yaml)
  d="$out/${name}_$s"
  if "$sim" --scenario "$f" --seed "$s" --quiet --no-plots --out "$d" >"$d.log" 2>&1 || [ -f "$d/trajectory.csv" ]; then
    echo "$name $s $(sha256sum <"$d/trajectory.csv" | cut -c1-16)"
  else
    echo "$name $s no-trajectory(exit)"
  fi
}
export -f run_one
printf '%s\n' "${jobs[@]}" | xargs -P "${JOBS:-2}" -L1 bash -c 'run_one $0 $1 "'"$sim"'" "'"$out"'"' | sort
