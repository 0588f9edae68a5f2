# Run after each link of the test executable (tests/CMakeLists.txt): writes CTEST_FILE, a CTest
# script that gives each test Catch discovered its labels and its timeout.
#   TEST_EXECUTABLE  the Catch executable
#   LABELS           "label=spec|label=spec|...": a test gets the label when the Catch test spec
#                    (tags, ',' for or) lists it; a test may get several, a label several specs
#   TIMEOUT          seconds, for every test
#   LONG_LABEL, LONG_TIMEOUT  the tests with that label get the longer timeout instead
# catch_discover_tests can only give one set of properties to all the tests it finds, and a second
# discovery per label would add each test twice; asking the executable which tests each spec lists
# and setting the labels afterwards keeps the tests and their names as discovery made them.

cmake_minimum_required(VERSION 3.22)  # as the project; if(IN_LIST) needs 3.3 policies in a -P script

string(REPLACE "|" ";" label_specs "${LABELS}")
set(labelled "")
foreach(entry IN LISTS label_specs)
  string(FIND "${entry}" "=" at)
  string(SUBSTRING "${entry}" 0 ${at} label)
  math(EXPR at "${at} + 1")
  string(SUBSTRING "${entry}" ${at} -1 spec)
  execute_process(
    COMMAND "${TEST_EXECUTABLE}" "${spec}" --list-test-names-only
    OUTPUT_VARIABLE output
    RESULT_VARIABLE result)
  # Catch exits with the number of tests listed (modulo 256): anything but a number is a failure.
  if(NOT result MATCHES "^[0-9]+$")
    message(FATAL_ERROR "${TEST_EXECUTABLE} ${spec} --list-test-names-only: ${result}\n${output}")
  endif()
  if(output STREQUAL "")
    message(FATAL_ERROR "CTest label ${label}: the Catch test spec ${spec} lists no test")
  endif()
  # One list element per line; a name holding a ';' splits in two here just as CatchAddTests splits
  # it into two CTest tests, so the names stay CTest's. Brackets would bind elements together in a
  # CMake list, so they are escaped for the loop and restored after.
  string(REPLACE "[" "<lb>" output "${output}")
  string(REPLACE "]" "<rb>" output "${output}")
  string(REPLACE "\n" ";" names "${output}")
  foreach(name IN LISTS names)
    if(name STREQUAL "")
      continue()
    endif()
    string(MD5 key "${name}")
    if(NOT DEFINED labels_${key})
      list(APPEND labelled "${name}")
    endif()
    list(APPEND labels_${key} ${label})
    list(REMOVE_DUPLICATES labels_${key})
  endforeach()
endforeach()

set(script "")
foreach(name IN LISTS labelled)
  string(MD5 key "${name}")
  set(timeout ${TIMEOUT})
  if(LONG_LABEL IN_LIST labels_${key})
    set(timeout ${LONG_TIMEOUT})
  endif()
  string(REPLACE "<lb>" "[" test "${name}")
  string(REPLACE "<rb>" "]" test "${test}")
  string(APPEND script "set_tests_properties([==[${test}]==] PROPERTIES LABELS \"${labels_${key}}\" TIMEOUT ${timeout})\n")
endforeach()
file(WRITE "${CTEST_FILE}" "${script}")
