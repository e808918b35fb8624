# Issue 11: the sections and mission types of missions on a map (localisation, odometry drift,
# goto goals, waypoints, coverage) as the scenario loader reads them.
carril_add_test(scenario_missions_on_map_test SOURCES ScenarioMissionsOnMapTest.cpp
  LIBS carril_sim_scenario)
target_compile_definitions(scenario_missions_on_map_test PRIVATE
  CARRIL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
