# The scripts a newcomer runs first refuse a bad argument with exit code 2 and one line on stderr
# naming it, before they install or build anything. Run as
#   cmake -DSRC=<source dir> -P scripts_args.cmake
cmake_minimum_required(VERSION 3.19)
if(NOT DEFINED SRC)
  message(FATAL_ERROR "scripts_args.cmake: pass -DSRC=...")
endif()
set(FAILURES "")
foreach(script bootstrap.sh test.sh)
  execute_process(COMMAND "${SRC}/scripts/${script}" --no-such-option
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 30)
  string(REGEX MATCHALL "\n" newlines "${err}")
  list(LENGTH newlines lines)
  if(NOT "${rc}" STREQUAL "2" OR NOT lines EQUAL 1 OR NOT err MATCHES "unknown argument '--no-such-option'" OR NOT out STREQUAL "")
    string(APPEND FAILURES "\n  scripts/${script} --no-such-option: exit '${rc}' (expected 2), stderr '${err}', stdout '${out}'")
  endif()
endforeach()
if(FAILURES)
  message(FATAL_ERROR "scripts:${FAILURES}")
endif()
