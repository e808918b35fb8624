# Issue 11: Monte Carlo localisation (firmware/estimation/MonteCarloLocalizer.hpp and its parts).
carril_add_test(estimation_mcl_field_test SOURCES MclFieldTest.cpp LIBS carril_firmware)
carril_add_test(estimation_mcl_sampling_test SOURCES MclSamplingTest.cpp LIBS carril_firmware)
carril_add_test(estimation_mcl_localizer_test SOURCES MclLocalizerTest.cpp
  LIBS carril_firmware carril_alloc_counter)
# The localiser's inline draws (MclRandom.hpp, MclMath.hpp) compiled here as in the firmware:
# without FMA contraction, so the golden values hold on aarch64 too.
foreach(t estimation_mcl_field_test estimation_mcl_sampling_test estimation_mcl_localizer_test)
  if(TARGET ${t})
    target_compile_options(${t} PRIVATE -ffp-contract=off)
  endif()
endforeach()
