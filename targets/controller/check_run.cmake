# Runs a command and checks its exit status and output; fails (exit 1) on any mismatch.
#   cmake -DCOMMAND=<argv joined with |> -DEXPECT_EXIT=<n> [-DEXPECT_STDOUT=<regex>]
#         [-DEXPECT_STDERR=<regex>] -P check_run.cmake
# ('.' in a CMake regex also matches newlines, so one regex can span several lines.)
if(NOT DEFINED COMMAND OR NOT DEFINED EXPECT_EXIT)
  message(FATAL_ERROR "check_run.cmake: COMMAND and EXPECT_EXIT are required")
endif()
string(REPLACE "|" ";" argv "${COMMAND}")
execute_process(COMMAND ${argv} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("command: ${argv}\nexit: ${rc}\n--- stdout ---\n${out}--- stderr ---\n${err}--------------")

set(problems "")
if(NOT rc STREQUAL EXPECT_EXIT)
  string(APPEND problems "  exit status ${rc}, expected ${EXPECT_EXIT}\n")
endif()
if(DEFINED EXPECT_STDOUT AND NOT out MATCHES "${EXPECT_STDOUT}")
  string(APPEND problems "  stdout does not match: ${EXPECT_STDOUT}\n")
endif()
if(DEFINED EXPECT_STDERR AND NOT err MATCHES "${EXPECT_STDERR}")
  string(APPEND problems "  stderr does not match: ${EXPECT_STDERR}\n")
endif()
if(problems)
  message(FATAL_ERROR "check_run.cmake: FAILED\n${problems}")
endif()
