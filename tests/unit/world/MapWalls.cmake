# Issue 11: simulator walls from a scenario's occupancy map (host_sim/world/MapWalls.hpp), seen
# by the 2D lidar and the robot's contacts; the test reads the shipped maps in scenarios/maps.
carril_add_test(sim_map_walls_test SOURCES MapWallsTest.cpp
  LIBS carril_sim_world carril_sim_scenario carril_sim_sensors)
target_compile_definitions(sim_map_walls_test PRIVATE CARRIL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
