# Cross toolchain for the robot's ARM Linux computer: Debian's g++-aarch64-linux-gnu.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# Target libraries come from the cross sysroot; header-only Eigen is shared with the host.
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
# Cross-built tests run under qemu-user, against Debian's arm64 runtime (libc6:arm64,
# libstdc++6:arm64, libyaml-cpp0.7:arm64 in /lib/aarch64-linux-gnu; tools/setup.sh installs them),
# as on the robot. Not against the cross sysroot: its dynamic loader would search
# /lib/aarch64-linux-gnu too and load that libc, mixing two builds of glibc in one process.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /)
