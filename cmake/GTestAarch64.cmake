# GoogleTest for the aarch64 cross build, as the target `GTest::gtest` (the name the host's
# package gives it).
#
# Debian ships no arm64 GoogleTest that installs beside the host's libgtest-dev, but it ships the
# sources (package googletest, in /usr/src/googletest; tools/setup.sh installs it): they are built
# here with the cross compiler, as part of this build. Only gtest: no carril test uses gmock.
set(CARRIL_GTEST_SOURCE_DIR /usr/src/googletest
    CACHE PATH "GoogleTest sources (Debian package googletest)")
if(NOT EXISTS ${CARRIL_GTEST_SOURCE_DIR}/CMakeLists.txt)
  message(FATAL_ERROR "aarch64 build: no GoogleTest sources in ${CARRIL_GTEST_SOURCE_DIR}; "
                      "install the package googletest (bash tools/setup.sh)")
endif()

set(BUILD_GMOCK OFF CACHE BOOL "carril: the cross build needs gtest only" FORCE)
set(INSTALL_GTEST OFF CACHE BOOL "carril: GoogleTest is built for the tests, not installed" FORCE)
# SYSTEM: its headers are third-party code, outside carril's warning rules. EXCLUDE_FROM_ALL:
# built only as far as a test links it.
add_subdirectory(${CARRIL_GTEST_SOURCE_DIR} ${CMAKE_BINARY_DIR}/googletest EXCLUDE_FROM_ALL SYSTEM)
if(NOT TARGET GTest::gtest)
  message(FATAL_ERROR "aarch64 build: ${CARRIL_GTEST_SOURCE_DIR} did not define GTest::gtest")
endif()
# GCC 12 reports a false -Wrestrict inside libstdc++ for GoogleTest's "literal" + std::string
# (GCC bug 105329), as for the loader.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(gtest PRIVATE -Wno-restrict)
endif()
