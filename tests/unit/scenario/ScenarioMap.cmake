# Issue 11: the scenario key `map:` (an occupancy map in ROS map_server's format).
carril_add_test(scenario_map_test SOURCES ScenarioMapTest.cpp LIBS carril_sim_scenario)
target_compile_definitions(scenario_map_test PRIVATE CARRIL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
