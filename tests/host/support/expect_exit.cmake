# cmake -DEXPECTED_EXIT=N [-DEXPECT_OUTPUT=REGEX] [-DREQUIRES=PATH] -P expect_exit.cmake -- COMMAND ARGS...:
# runs the command, echoes its output and fails unless it exits with N and, with EXPECT_OUTPUT,
# its output (stdout then stderr) matches REGEX. Both are checked: a tool that prints the right
# text and then crashes fails, and so does one that exits right and prints the wrong text
# (ctest's PASS_REGULAR_EXPRESSION alone would ignore the exit status). The `--` keeps cmake from
# reading the command's own options (--help, --version) as its own. In the sanitizer build a
# report ends the tool with exit 23 (cmake/sanitizer_defaults.cpp), which no test expects, so a
# memory error never passes for an expected exit 1 or 2.
# With REQUIRES: when PATH (recorded data) is missing the test is skipped ("ALE_SKIP", see
# ale_cli_test), or fails when CI=true.
cmake_policy(SET CMP0007 NEW)
if(DEFINED REQUIRES AND NOT EXISTS "${REQUIRES}")
  if("$ENV{CI}" STREQUAL "true")
    message(FATAL_ERROR "CI=true but test data is missing: ${REQUIRES}")
  endif()
  message("ALE_SKIP: test data missing (${REQUIRES}); set ALE_DATA_DIR or put ../shared/data beside the repository")
  return()
endif()
set(_cmd)
set(_past_script FALSE)
math(EXPR _last "${CMAKE_ARGC} - 1")
foreach(i RANGE ${_last})
  if(_past_script)
    if(NOT _cmd AND "${CMAKE_ARGV${i}}" STREQUAL "--")
      continue()
    endif()
    list(APPEND _cmd "${CMAKE_ARGV${i}}")
  elseif("${CMAKE_ARGV${i}}" MATCHES "expect_exit\\.cmake$")
    set(_past_script TRUE)
  endif()
endforeach()
if(NOT _cmd)
  message(FATAL_ERROR "expect_exit.cmake: no command given")
endif()
execute_process(COMMAND ${_cmd} RESULT_VARIABLE _exit OUTPUT_VARIABLE _out ERROR_VARIABLE _err)
message("${_out}${_err}")
set(_failed FALSE)
if(NOT "${_exit}" STREQUAL "${EXPECTED_EXIT}")
  message(SEND_ERROR "exit status ${_exit}, expected ${EXPECTED_EXIT}")
  set(_failed TRUE)
endif()
if(DEFINED EXPECT_OUTPUT AND NOT "${_out}${_err}" MATCHES "${EXPECT_OUTPUT}")
  message(SEND_ERROR "output does not match: ${EXPECT_OUTPUT}")
  set(_failed TRUE)
endif()
if(_failed)
  message(FATAL_ERROR "${_cmd}")
endif()
