# Issue 11: a mission file on a known map (map:, localisation:) for carril_controller, and the
# firmware set-up the simulator shares (loader/MapMission.hpp).
carril_add_test(loader_map_mission_test SOURCES MapMissionTest.cpp LIBS carril_loader)
target_compile_definitions(loader_map_mission_test PRIVATE CARRIL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
