# yaml-cpp for the aarch64 cross build, as the IMPORTED target `yaml-cpp` (the name the host's
# package gives it).
#
# Debian's libyaml-cpp-dev:arm64 conflicts with the host's libyaml-cpp-dev, so the cross build
# links the arm64 runtime library (libyaml-cpp0.7:arm64, co-installable; tools/setup.sh installs
# it) by its full path and compiles against the host's headers, which do not depend on the
# architecture. Under qemu the library is found where Debian installs it (the emulator runs on
# Debian's arm64 runtime: cmake/toolchain-aarch64.cmake).
set(CARRIL_YAML_CPP_AARCH64_LIBRARY /usr/lib/aarch64-linux-gnu/libyaml-cpp.so.0.7
    CACHE FILEPATH "arm64 yaml-cpp runtime library (Debian package libyaml-cpp0.7:arm64)")
set(CARRIL_YAML_CPP_HEADERS /usr/include/yaml-cpp
    CACHE PATH "yaml-cpp headers (the host's libyaml-cpp-dev; architecture-independent)")
if(NOT EXISTS ${CARRIL_YAML_CPP_AARCH64_LIBRARY})
  message(FATAL_ERROR "aarch64 build: ${CARRIL_YAML_CPP_AARCH64_LIBRARY} is missing; install "
                      "libyaml-cpp0.7:arm64 (bash tools/setup.sh)")
endif()
if(NOT EXISTS ${CARRIL_YAML_CPP_HEADERS}/yaml.h)
  message(FATAL_ERROR "aarch64 build: ${CARRIL_YAML_CPP_HEADERS}/yaml.h is missing; install "
                      "libyaml-cpp-dev (bash tools/setup.sh)")
endif()

# The headers through a directory that holds only them: an include path of /usr/include would
# hand the cross compiler the host's libc headers.
set(yaml_include ${CMAKE_BINARY_DIR}/yaml-cpp-aarch64/include)
file(MAKE_DIRECTORY ${yaml_include})
if(NOT EXISTS ${yaml_include}/yaml-cpp)
  file(CREATE_LINK ${CARRIL_YAML_CPP_HEADERS} ${yaml_include}/yaml-cpp SYMBOLIC)
endif()

get_filename_component(yaml_soname ${CARRIL_YAML_CPP_AARCH64_LIBRARY} NAME)
add_library(yaml-cpp SHARED IMPORTED)
set_target_properties(yaml-cpp PROPERTIES
  IMPORTED_LOCATION ${CARRIL_YAML_CPP_AARCH64_LIBRARY}
  IMPORTED_SONAME ${yaml_soname}
  INTERFACE_INCLUDE_DIRECTORIES ${yaml_include})
