# check_test_count.cmake: run by ctest (tests/CMakeLists.txt) after test discovery. Fails unless
# the Catch2 test cases that ctest runs are exactly the ones the test programs list, one ctest
# entry per test case, with the same names, and no test case name contains ';', '[' or ']'.
#
# Why: catch_discover_tests turns each program's list into a CMake list. A ';' in a name splits
# it into two ctest entries whose filters match nothing; an unmatched ']' merges that case and the
# ones after it into one entry. Catch2 v2 answers "No test cases matched" and, without -w NoTests,
# exits 0, so those cases were reported as passed without running.
#
# Inputs (-D): PROGRAMS_FILE (lines "prefix<TAB>program path", written by tests/CMakeLists.txt),
# CTEST_COMMAND, BUILD_DIR (where ctest lists the tests), SELF (this check's own ctest name).
# Benchmark smoke tests (label "smoke"), examples run as tests (label "example") and this check
# with its self-test (label "test_count") are
# not Catch2 cases and are left out (ctest -LE).
cmake_minimum_required(VERSION 3.20)

foreach(var PROGRAMS_FILE CTEST_COMMAND BUILD_DIR SELF)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_test_count.cmake: -D${var}=... is required")
  endif()
endforeach()

# CMake lists split at ';' and treat '[' ']' specially: hide the three characters behind
# placeholders before any list operation, and restore them only in messages.
set(_semi "<SEMICOLON>")
set(_lb "<LBRACKET>")
set(_rb "<RBRACKET>")
function(hide_specials out text)
  string(REPLACE ";" "${_semi}" text "${text}")
  string(REPLACE "[" "${_lb}" text "${text}")
  string(REPLACE "]" "${_rb}" text "${text}")
  string(REPLACE "\r" "" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()
function(show_specials out text)
  string(REPLACE "${_semi}" ";" text "${text}")
  string(REPLACE "${_lb}" "[" text "${text}")
  string(REPLACE "${_rb}" "]" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

# 1. What the programs list.
file(READ "${PROGRAMS_FILE}" programs_text)
hide_specials(programs_text "${programs_text}")
string(REPLACE "\n" ";" program_lines "${programs_text}")
set(expected "")
set(bad_names "")
set(listed 0)
foreach(line IN LISTS program_lines)
  if(line STREQUAL "")
    continue()
  endif()
  string(FIND "${line}" "\t" tab)
  string(SUBSTRING "${line}" 0 ${tab} prefix)
  math(EXPR after "${tab} + 1")
  string(SUBSTRING "${line}" ${after} -1 program)
  show_specials(program "${program}")
  execute_process(COMMAND "${program}" --list-test-names-only
                  OUTPUT_VARIABLE names RESULT_VARIABLE rc ERROR_VARIABLE err)
  # Catch2 v2 exits with the number of test cases listed; anything not a number is a failure.
  if(NOT rc MATCHES "^[0-9]+$")
    message(FATAL_ERROR "check_test_count.cmake: '${program} --list-test-names-only' failed: ${rc}\n${err}")
  endif()
  hide_specials(names "${names}")
  string(REPLACE "\n" ";" names "${names}")
  foreach(name IN LISTS names)
    if(name STREQUAL "")
      continue()
    endif()
    math(EXPR listed "${listed} + 1")
    if(name MATCHES "${_semi}|${_lb}|${_rb}")
      show_specials(shown "${prefix}${name}")
      string(APPEND bad_names "\n  ${shown}")
    endif()
    list(APPEND expected "${prefix}${name}")
  endforeach()
endforeach()

# 2. What ctest runs (benchmark smoke tests and the test_count checks left out).
execute_process(COMMAND "${CTEST_COMMAND}" -N -LE "^(smoke|example|test_count)$" WORKING_DIRECTORY "${BUILD_DIR}"
                OUTPUT_VARIABLE ctest_text RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "check_test_count.cmake: 'ctest -N' failed (${rc}):\n${err}")
endif()
hide_specials(ctest_text "${ctest_text}")
hide_specials(self "${SELF}")
string(REPLACE "\n" ";" ctest_lines "${ctest_text}")
set(registered "")
foreach(line IN LISTS ctest_lines)
  if(line MATCHES "^ *Test +#[0-9]+: (.*)$")
    set(name "${CMAKE_MATCH_1}")
    if(NOT name STREQUAL self)
      list(APPEND registered "${name}")
    endif()
  endif()
endforeach()

# 3. Compare as multisets: a name registered twice or listed twice is also a difference.
set(only_listed "")
set(only_registered "")
set(remaining "${registered}")
foreach(name IN LISTS expected)
  list(FIND remaining "${name}" at)
  if(at EQUAL -1)
    show_specials(shown "${name}")
    string(APPEND only_listed "\n  ${shown}")
  else()
    list(REMOVE_AT remaining ${at})
  endif()
endforeach()
foreach(name IN LISTS remaining)
  show_specials(shown "${name}")
  string(APPEND only_registered "\n  ${shown}")
endforeach()

list(LENGTH registered n_registered)
set(report "")
if(NOT bad_names STREQUAL "")
  string(APPEND report "test case names must not contain ';', '[' or ']' (catch_discover_tests splits or merges them):${bad_names}\n")
endif()
if(NOT listed EQUAL n_registered)
  string(APPEND report "the test programs list ${listed} test cases, ctest registers ${n_registered}\n")
endif()
if(NOT only_listed STREQUAL "")
  string(APPEND report "listed by a test program but not a ctest entry of that name (never run):${only_listed}\n")
endif()
if(NOT only_registered STREQUAL "")
  string(APPEND report "ctest entries that are not exactly one listed test case:${only_registered}\n")
endif()
if(NOT report STREQUAL "")
  message(FATAL_ERROR "check_test_count.cmake:\n${report}")
endif()
message(STATUS "ctest registers the ${listed} test cases the programs list, one entry each")
