# Issue 11: the waypoint course followed with VFF; the body guard (corners clear when turning).
carril_add_test(waypoint_mission_test
  SOURCES WaypointMissionTest.cpp WaypointCourseTest.cpp BodyGuardTest.cpp
  LIBS carril_firmware carril_alloc_counter)
