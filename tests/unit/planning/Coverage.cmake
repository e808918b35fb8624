# Issue 11, coverage: the boustrophedon decomposition, its lanes and tour, and the coverage area.
carril_add_test(planning_boustrophedon_test SOURCES BoustrophedonTest.cpp
  LIBS carril_fw_planning carril_alloc_counter)
