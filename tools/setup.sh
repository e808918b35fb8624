#!/usr/bin/env bash
# Installs the Debian packages carril needs, and only those that are missing (idempotent).
# Nothing is downloaded from anywhere but Debian's archive. Quiet: one line saying that all are
# present or what it installs; apt's output goes to a log that is shown only when apt fails.
set -euo pipefail
packages=(
  cmake g++ make pkg-config
  libeigen3-dev libopencv-dev libbox2d-dev libyaml-cpp-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  g++-aarch64-linux-gnu qemu-user
  # GoogleTest's sources: the aarch64 cross build compiles them for its unit tests.
  googletest
  # The robot target reads its configuration with yaml-cpp: the arm64 runtime library (with
  # Debian's arm64 libc and libstdc++ as its dependencies) for the cross build and for qemu.
  # Not libyaml-cpp-dev:arm64, which would replace the host's libyaml-cpp-dev.
  libyaml-cpp0.7:arm64
  can-utils user-mode-linux kmod iproute2 # CAN HIL: a real kernel with vcan (tools/uml)
  rt-tests
  clang libclang-rt-14-dev # libclang-rt-14-dev holds libFuzzer (-fsanitize=fuzzer)
  slurm-wlm munge
  python3
  ccache # developers: cmake --preset host -DCMAKE_CXX_COMPILER_LAUNCHER=ccache rebuilds faster
  libboost-dev # Boost.Graph: the oracle of the wavefront planner's benchmark
)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi
echo "setup: installing ${missing[*]} (apt-get, may take a while)"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
log=$(mktemp "${TMPDIR:-/tmp}/carril-setup.XXXXXX.log")
export DEBIAN_FRONTEND=noninteractive
# arm64 packages need the architecture enabled (once) before apt-get update lists them.
add_arm64=(true)
if ! dpkg --print-foreign-architectures | grep -qx arm64; then
  add_arm64=("${sudo_cmd[@]}" dpkg --add-architecture arm64)
fi
if ! { "${add_arm64[@]}" && "${sudo_cmd[@]}" apt-get update -q &&
  "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"; } \
  </dev/null >"$log" 2>&1; then
  echo "setup: apt-get failed; the last lines of its log ($log):" >&2
  tail -n 40 "$log" >&2
  exit 1
fi
rm -f "$log"
