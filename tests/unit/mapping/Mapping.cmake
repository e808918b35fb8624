# The Mapping component's terrain cycle in pieces against the whole computation.
carril_add_test(mapping_component_test SOURCES MappingTest.cpp LIBS carril_firmware)
