# Issue 10: elevation fusion of a 32 x 1800 sweep, and terrain analysis against a per-cell Eigen
# PCA plane fit (grid_map's normal filter's method).
add_executable(bench_terrain ${CMAKE_CURRENT_SOURCE_DIR}/TerrainBench.cpp)
target_include_directories(bench_terrain PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(bench_terrain PRIVATE carril_firmware benchmark::benchmark)
