# Issue 11, coverage: how often a cleaning tool swept each cell.
carril_add_test(mapping_coverage_grid_test SOURCES CoverageGridTest.cpp
  LIBS carril_fw_mapping carril_alloc_counter)
