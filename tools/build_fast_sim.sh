#!/usr/bin/env bash
# The fastest simulator: carril_sim (and carril_campaign beside it) built with GCC's
# profile-guided and link-time optimisation in build/sim-pgo, for campaigns and speed figures. It
# builds an instrumented carril_sim, runs it on the training scenarios, and rebuilds it with those
# profiles.
# The runs' results are the same as the host preset's to the bit; only the speed differs
# (docs/performance.md). The square scenario, the speed benchmark, is left out of the training.
# Its tests (ctest --test-dir build/sim-pgo -L fast_sim, in the README's test command) compare its
# runs with the host preset's carril_sim, or with $CARRIL_REFERENCE_SIM's.
# Usage: bash tools/build_fast_sim.sh   (prints the simulator's path last)
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
dir=build/sim-pgo
prof=$PWD/$dir/pgo-profiles
jobs=$(nproc)
# Training: the five thesis courses the campaigns run (camera, tape, lidar and costmap at their
# rates), an obstacle bypass and a corridor blocked wall to wall.
training=(corners smooth circle corners_red smooth_red bypass_other_side corridor_blocked)
rm -rf "$prof"
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DCMAKE_INTERPROCEDURAL_OPTIMIZATION=ON \
  -DCARRIL_PGO=generate -DCARRIL_PGO_DIR="$prof" >/dev/null
cmake --build "$dir" -j"$jobs" --target carril_sim >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for s in "${training[@]}"; do
  # A scenario's verdict does not matter here, only that it ran to its end.
  rc=0
  "$dir/host_sim/app/carril_sim" --scenario "scenarios/$s.yaml" --quiet --no-plots \
    --out "$out/$s" >/dev/null || rc=$?
  if [ "$rc" -gt 1 ]; then
    echo "build_fast_sim: training run scenarios/$s.yaml failed (exit $rc)" >&2
    exit 1
  fi
done
ref=${CARRIL_REFERENCE_SIM:-$PWD/build/host/host_sim/app/carril_sim}
cmake -S . -B "$dir" -DCARRIL_PGO=use -DCARRIL_REFERENCE_SIM="$ref" >/dev/null
cmake --build "$dir" -j"$jobs" --target carril_sim carril_campaign >/dev/null
echo "$dir/host_sim/app/carril_sim"
