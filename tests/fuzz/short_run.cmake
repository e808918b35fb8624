# One short, deterministic fuzz run (CTest fuzz.<name>): a fresh working corpus in WORK (libFuzzer
# writes the inputs it finds into its first corpus directory, so never into the source tree),
# then the seeds and regressions of CORPUS (read recursively: CORPUS/regressions/ included),
# seed 1, RUNS executions. Fails on any crash, leak, timeout or sanitizer report.
#   cmake -DFUZZER=exe -DCORPUS=dir -DWORK=dir -DRUNS=n -P short_run.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/corpus ${WORK}/artifacts)
execute_process(
  COMMAND ${FUZZER} -seed=1 -runs=${RUNS} -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
          -artifact_prefix=${WORK}/artifacts/ ${WORK}/corpus ${CORPUS}
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${FUZZER} failed (exit ${rc}); the input is in ${WORK}/artifacts/")
endif()
