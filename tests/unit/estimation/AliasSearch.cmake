# Issue 11: the alias check of a regained pose (firmware/estimation/AliasSearch.hpp).
carril_add_test(estimation_alias_search_test SOURCES AliasSearchTest.cpp LIBS carril_firmware)
