# Issue 11: Monte Carlo localisation: one update of 2000 particles x 60 beams against its floor
# (the same endpoint transforms and likelihood-field lookups alone), resampling from 1000 to 16000
# particles (and AMCL's quadratic draw), and the time of one step() per particle budget
# (docs/performance.md).
add_executable(bench_mcl MclBench.cpp)
target_include_directories(bench_mcl PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(bench_mcl PRIVATE carril_firmware benchmark::benchmark)
