# Issue 11: occupancy maps in ROS map_server's format (loader/OccupancyMapFile.hpp); the test
# also loads the shipped maps in scenarios/maps.
carril_add_test(loader_occupancy_map_test SOURCES OccupancyMapFileTest.cpp
  LIBS carril_loader yaml-cpp)
target_compile_definitions(loader_occupancy_map_test PRIVATE
  CARRIL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
