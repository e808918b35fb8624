# Issue 10, costmap layers: ray tracing, obstacle layer, inflation, layered costmap.
carril_add_test(mapping_grid_ray_test SOURCES GridRayTest.cpp LIBS carril_firmware)
carril_add_test(mapping_obstacle_layer_test SOURCES ObstacleLayerTest.cpp
  LIBS carril_firmware carril_alloc_counter)
carril_add_test(mapping_inflation_layer_test SOURCES InflationLayerTest.cpp
  LIBS carril_firmware carril_alloc_counter)
carril_add_test(mapping_layered_costmap_test SOURCES LayeredCostmapTest.cpp
  LIBS carril_firmware carril_alloc_counter)
