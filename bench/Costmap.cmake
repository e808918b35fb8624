# Issue 10, costmap layers: inflation against OpenCV's exact distance transform, and one obstacle
# layer update plus inflation of the 240 x 240 window.
add_executable(bench_costmap CostmapBench.cpp)
target_include_directories(bench_costmap PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(bench_costmap PRIVATE carril_firmware opencv_core opencv_imgproc
  benchmark::benchmark)
