# Issue 11, coverage: the patches a cleaning run has left, for its revisits.
carril_add_test(mapping_unswept_patches_test SOURCES UnsweptPatchesTest.cpp LIBS carril_fw_mapping)
