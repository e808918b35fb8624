# Issue 11: the Localisation component (odometry passed through without a map; MCL on one).
carril_add_test(estimation_localisation_test SOURCES LocalisationTest.cpp
  LIBS carril_firmware carril_alloc_counter)
