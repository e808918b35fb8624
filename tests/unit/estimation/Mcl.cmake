# Issue 11: Monte Carlo localisation (firmware/estimation/MonteCarloLocalizer.hpp and its parts).
carril_add_test(estimation_mcl_field_test SOURCES MclFieldTest.cpp LIBS carril_firmware)
carril_add_test(estimation_mcl_sampling_test SOURCES MclSamplingTest.cpp LIBS carril_firmware)
carril_add_test(estimation_mcl_localizer_test SOURCES MclLocalizerTest.cpp
  LIBS carril_firmware carril_test_alloc_counter)
