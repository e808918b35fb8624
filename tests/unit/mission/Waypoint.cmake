# Issue 11: the waypoint course followed with VFF.
carril_add_test(waypoint_mission_test SOURCES WaypointMissionTest.cpp
  LIBS carril_firmware carril_test_alloc_counter)
