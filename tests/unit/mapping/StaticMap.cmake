# Issue 11: the static occupancy map and its costmap layer.
carril_add_test(mapping_static_map_test SOURCES StaticLayerTest.cpp LIBS carril_firmware)
