# Issue 10: saved elevation maps. CRC-32 against zlib's crc32 (the reference), encoding field by
# field against a plain memcpy of the cells (the non-portable layout), and a whole load.
find_package(ZLIB REQUIRED)
add_executable(bench_map_file MapFileBench.cpp)
target_include_directories(bench_map_file PRIVATE ${CMAKE_BINARY_DIR}/include-trees/loader)
target_link_libraries(bench_map_file PRIVATE carril_loader ZLIB::ZLIB benchmark::benchmark)
