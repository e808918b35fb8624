# Issue 12: the bypass lane check (whole body against lethal cells) against the centre-only walk
# it replaced, on the same lane.
add_executable(bench_bypass ${CMAKE_CURRENT_SOURCE_DIR}/BypassBench.cpp)
target_include_directories(bench_bypass PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(bench_bypass PRIVATE carril_firmware benchmark::benchmark)
