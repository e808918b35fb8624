# Issue 10: one simulated HDL-32E sweep over a terrain scene, against a uniform 1 cm march.
add_executable(bench_lidar3d ${CMAKE_CURRENT_SOURCE_DIR}/Lidar3dBench.cpp)
target_include_directories(bench_lidar3d PRIVATE ${CARRIL_PRODUCT_INCLUDE})
target_link_libraries(bench_lidar3d PRIVATE carril_sim_sensors benchmark::benchmark)
