# Issue 11, coverage: the coverage mission (systematic and vacuum) in a kinematic loop.
carril_add_test(mission_coverage_test SOURCES CoverageMissionTest.cpp
  LIBS carril_fw_mission carril_alloc_counter)
