# Issue 10 item 10: the wavefront planner against Boost.Graph's dijkstra_shortest_paths on the
# same 8-connected 1000 x 1000 grid with the same edge weights (docs/performance.md).
find_package(Boost QUIET)
if(Boost_FOUND)
  add_executable(bench_wavefront WavefrontBench.cpp)
  target_include_directories(bench_wavefront PRIVATE ${PROJECT_SOURCE_DIR})
  target_link_libraries(bench_wavefront PRIVATE carril_firmware Boost::headers benchmark::benchmark)
else()
  message(STATUS "bench_wavefront left out: Boost (libboost-dev) not found")
endif()
