# The harness of the CLI-contract scripts (cli_errors, cli_inputs, cli_outputs, cli_names, cli_stats,
# cli_export, cli_diff): their common start and end, and expect_error() and expect_warning(). A script
# gets RAYSPACE (the executable) and WORK (the scratch directory) as -D variables and collects
# FAILURES and CASES.
#
# cli_script_begin(<script> [<var>...]): stops with "<script>: pass -D<var>=..." when a -D variable
# the script needs is missing, empties WORK, unsets RAYSPACE_DATA (a user's data root must not change
# what the scripts see) and starts FAILURES and CASES.
macro(cli_script_begin script)
  foreach(_cli_var ${ARGN})
    if(NOT DEFINED ${_cli_var} OR "${${_cli_var}}" STREQUAL "")
      message(FATAL_ERROR "${script}: pass -D${_cli_var}=...")
    endif()
  endforeach()
  file(REMOVE_RECURSE "${WORK}")
  file(MAKE_DIRECTORY "${WORK}")
  unset(ENV{RAYSPACE_DATA})
  set(FAILURES "")
  set(CASES 0)
endmacro()

# cli_script_end(<test>): fails the script listing FAILURES, or says all CASES passed.
macro(cli_script_end test)
  if(NOT FAILURES STREQUAL "")
    message(FATAL_ERROR "${test}: failures among ${CASES} cases:${FAILURES}")
  endif()
  message(STATUS "${test}: all ${CASES} cases passed")
endmacro()

# cli_require_data(<test> [<file>...]): ends the script with "data root not found: <DATA> ... <test>
# skipped" when DATA lacks Sponza (every data test reads it) or one of the other files named, relative
# to DATA; tests/CMakeLists.txt's SKIP_REGULAR_EXPRESSION turns that line into a skip. A macro, so
# that its return() ends the script.
macro(cli_require_data test)
  foreach(_cli_file sponza_dabrovic/sponza.obj ${ARGN})
    if(NOT EXISTS "${DATA}/${_cli_file}")
      message(STATUS "data root not found: ${DATA} (no ${_cli_file}): ${test} skipped")
      return()
    endif()
  endforeach()
endmacro()

# cli_case_begin(): for the scripts of one ctest per case (cli_diff, cli_export), which
# tests/CMakeLists.txt also includes with CASE unset to list the cases: when CASE is set, a scratch
# directory of its own, case_work (cases run in parallel), emptied first.
macro(cli_case_begin)
  set(FAILURES "")
  set(CASES 0)
  if(DEFINED CASE)
    string(REPLACE ":" "_" case_dir "${CASE}")
    set(case_work "${WORK}/${case_dir}")
    file(REMOVE_RECURSE "${case_work}")
    file(MAKE_DIRECTORY "${case_work}")
  endif()
endmacro()
#
# expect_error(NAME <case> NEEDLES <substring>... [ABSENT <path>...] [COMMAND <prefix>...]
#              [TIMEOUT <seconds>] ARGS <arg>...)
# Runs the CLI with ARGS in WORK (after COMMAND, e.g. a shell that sets a limit first); expects exit
# code 2, one line on stderr containing every needle, none of the ABSENT paths afterwards and no
# temporary output file (.NAME.tmp-*) left in WORK. A run that outlives TIMEOUT (default 120 s) is
# killed and fails the case, so a read that blocks (a FIFO without a writer) is reported instead of
# hanging the test.
function(expect_error)
  cmake_parse_arguments(E "" "NAME;TIMEOUT" "NEEDLES;ARGS;ABSENT;COMMAND" ${ARGN})
  if(NOT E_TIMEOUT)
    set(E_TIMEOUT 120)
  endif()
  math(EXPR n "${CASES} + 1")
  set(CASES ${n} PARENT_SCOPE)
  execute_process(COMMAND ${E_COMMAND} "${RAYSPACE}" ${E_ARGS}
                  WORKING_DIRECTORY "${WORK}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                  TIMEOUT ${E_TIMEOUT})
  set(problems "")
  if(NOT "${rc}" STREQUAL "2")
    list(APPEND problems "exit code '${rc}', expected 2")
  endif()
  # Exactly one line: ends in a newline and has no other.
  string(REGEX MATCHALL "\n" newlines "${err}")
  list(LENGTH newlines lines)
  string(LENGTH "${err}" len)
  if(len EQUAL 0)
    list(APPEND problems "stderr is empty")
  elseif(NOT lines EQUAL 1 OR NOT err MATCHES "\n$")
    list(APPEND problems "stderr is not exactly one line (${lines} newlines)")
  endif()
  if(err MATCHES "\r")
    list(APPEND problems "stderr contains a carriage return")
  endif()
  foreach(needle IN LISTS E_NEEDLES)
    string(FIND "${err}" "${needle}" at)
    if(at EQUAL -1)
      list(APPEND problems "stderr does not name '${needle}'")
    endif()
  endforeach()
  foreach(path IN LISTS E_ABSENT)
    if(EXISTS "${path}" OR IS_SYMLINK "${path}")
      list(APPEND problems "left behind: ${path}")
    endif()
  endforeach()
  file(GLOB temps "${WORK}/.*.tmp-*")
  if(temps)
    list(APPEND problems "temporary files left behind: ${temps}")
    file(REMOVE ${temps})
  endif()
  if(problems)
    string(REPLACE ";" "; " problems "${problems}")
    string(REPLACE ";" " " args "${E_ARGS}")
    set(FAILURES "${FAILURES}\n  [${E_NAME}] rayspace ${args}\n    ${problems}\n    stderr: ${err}" PARENT_SCOPE)
  else()
    string(STRIP "${err}" line)
    message(STATUS "ok: ${E_NAME}: ${line}")
  endif()
endfunction()

# expect_warning(NAME <case> [WARNINGS <n>] NEEDLES <substring>... ARGS <arg>...)
# Runs the CLI with ARGS in WORK; expects exit code 0, and on stderr WARNINGS (default 1) lines of
# the form "rayspace <cmd>: warning: ..." that together contain every needle. WARNINGS 0 checks that
# a flag the run does use draws no warning.
function(expect_warning)
  cmake_parse_arguments(E "" "NAME;WARNINGS" "NEEDLES;ARGS" ${ARGN})
  if(NOT DEFINED E_WARNINGS)
    set(E_WARNINGS 1)
  endif()
  math(EXPR n "${CASES} + 1")
  set(CASES ${n} PARENT_SCOPE)
  execute_process(COMMAND "${RAYSPACE}" ${E_ARGS} WORKING_DIRECTORY "${WORK}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
  set(problems "")
  if(NOT "${rc}" STREQUAL "0")
    list(APPEND problems "exit code '${rc}', expected 0")
  endif()
  string(REGEX MATCHALL "rayspace [a-z]+: warning: [^\n]*\n" warnings "${err}")
  string(REGEX MATCHALL "rayspace [a-z]+: warning: " prefixes "${err}")  # a warning may hold ';'
  list(LENGTH prefixes count)
  if(NOT count EQUAL E_WARNINGS)
    list(APPEND problems "${count} warning line(s), expected ${E_WARNINGS}")
  endif()
  foreach(needle IN LISTS E_NEEDLES)
    string(FIND "${warnings}" "${needle}" at)
    if(at EQUAL -1)
      list(APPEND problems "no warning names '${needle}'")
    endif()
  endforeach()
  if(problems)
    string(REPLACE ";" "; " problems "${problems}")
    string(REPLACE ";" " " args "${E_ARGS}")
    set(FAILURES "${FAILURES}\n  [${E_NAME}] rayspace ${args}\n    ${problems}\n    stderr: ${err}" PARENT_SCOPE)
  else()
    message(STATUS "ok: ${E_NAME}: ${warnings}")
  endif()
endfunction()
