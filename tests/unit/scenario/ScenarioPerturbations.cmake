# Issue 12: what campaigns perturb: tape_wear, glare, robot.camera.exposure, robot.lidar.dropout.
carril_add_test(scenario_perturbations_test SOURCES ScenarioPerturbationsTest.cpp
  LIBS carril_sim_scenario)
target_compile_definitions(scenario_perturbations_test PRIVATE
  CARRIL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
