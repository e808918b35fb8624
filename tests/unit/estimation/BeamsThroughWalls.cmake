# Negative information for a pose hypothesis: returns that cross the map's walls
# (firmware/estimation/BeamsThroughWalls.hpp).
carril_add_test(estimation_beams_through_walls_test SOURCES BeamsThroughWallsTest.cpp
  LIBS carril_firmware)
