#!/usr/bin/env bash
# The main job: install what is missing, build (host preset), and run the simulator on the
# default scenario, scenarios/corners.yaml (the whole mission: corners, two obstacles to get
# round, the stop on the end mark). Extra arguments go to carril_sim (e.g. --scenario scenarios/circle.yaml --view).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
cmake --preset host >/dev/null
cmake --build --preset host -j"$(nproc)" --target carril_sim
scenario=scenarios/corners.yaml
args=("$@")
for a in "$@"; do
  if [ "$a" = "--scenario" ]; then scenario=""; fi
done
if [ -n "$scenario" ]; then args=(--scenario "$scenario" "${args[@]}"); fi
set +e
./build/host/host_sim/app/carril_sim "${args[@]}"
rc=$?
set -e
echo "Plots: open the trajectory.png and velocities.png in the directory named above."
exit $rc
