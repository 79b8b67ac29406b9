# Run after a Catch2 test binary is built (see wedge_label_slow_tests in CMakeLists.txt): writes
# LABELS_FILE, which gives the ctest label `slow` to every test case tagged [slow].
execute_process(
  COMMAND "${TEST_EXECUTABLE}" "[slow]" --list-test-names-only
  OUTPUT_VARIABLE output
  RESULT_VARIABLE result)
# Catch2 v2 exits with the number of tests it listed; a negative value or a signal is an error.
if(NOT result MATCHES "^[0-9]+$")
  message(FATAL_ERROR "listing the [slow] tests of ${TEST_EXECUTABLE} failed: ${result}\n${output}")
endif()
string(REPLACE "\n" ";" names "${output}")
set(script "")
foreach(name IN LISTS names)
  if(name STREQUAL "")
    continue()
  endif()
  string(APPEND script "set_tests_properties([==[${TEST_PREFIX}${name}]==] PROPERTIES LABELS slow)\n")
endforeach()
file(WRITE "${LABELS_FILE}" "${script}")
