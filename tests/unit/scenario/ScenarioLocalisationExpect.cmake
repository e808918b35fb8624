# Issue 11: expect's localisation keys (convergence time, relocalisation time, RMSE).
carril_add_test(scenario_localisation_expect_test SOURCES ScenarioLocalisationExpectTest.cpp
  LIBS carril_sim_scenario)
target_compile_definitions(scenario_localisation_expect_test PRIVATE
  CARRIL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
