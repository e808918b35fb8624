# Issue 46: the protective and warning fields every motion passes through.
carril_add_test(safety_fields_test SOURCES SafetyFieldsTest.cpp MissionRunnerSafetyTest.cpp
  MotionCheckTest.cpp
  LIBS carril_firmware)
