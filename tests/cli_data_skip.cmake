# Without the data root, the tests that need it are reported as skipped, never passed: every script
# that calls cli_require_data (tests/cli_expect.cmake), run with a root that does not exist, prints
# "data root not found: <root>", and ctest, given the properties tests/CMakeLists.txt sets, lists
# them as skipped. Run as
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch dir> -DCTEST=<ctest> -P cli_data_skip.cmake
foreach(var RAYSPACE SRC WORK CTEST)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "cli_data_skip.cmake: pass -D${var}=...")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(root "${WORK}/no-such-data-root")
set(failures "")
set(tests "")
set(scripts cli_hierarchy cli_backend cli_data cli_sponza_thesis cli_reproduce cli_reproduce_quick cli_tl)
list(LENGTH scripts expected)
foreach(script ${scripts})
  set(part sponza)
  if(script STREQUAL "cli_tl")
    set(part data)
  endif()
  execute_process(COMMAND "${CMAKE_COMMAND}" -DRAYSPACE=${RAYSPACE} -DSRC=${SRC} -DDATA=${root} -DWORK=${WORK}/${script}
                          -DPART=${part} -P "${SRC}/tests/${script}.cmake"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT "${out}${err}" MATCHES "data root not found: ${root}")
    string(APPEND failures "\n${script}.cmake -DPART=sponza -DDATA=${root}: exit ${rc}, no 'data root not found: ${root}':\n${out}${err}")
  endif()
  string(APPEND tests "add_test(${script}.sponza \"${CMAKE_COMMAND}\" -DRAYSPACE=${RAYSPACE} -DSRC=${SRC} -DDATA=${root} "
                      "-DWORK=${WORK}/${script} -DPART=${part} -P \"${SRC}/tests/${script}.cmake\")\n"
                      "set_tests_properties(${script}.sponza PROPERTIES SKIP_REGULAR_EXPRESSION \"data root not found: \")\n")
endforeach()
# The same runs as ctest sees them.
file(WRITE "${WORK}/ctest/CTestTestfile.cmake" "${tests}")
execute_process(COMMAND "${CTEST}" WORKING_DIRECTORY "${WORK}/ctest" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(REGEX MATCHALL "\\*\\*\\*Skipped" skipped "${out}")
list(LENGTH skipped n)
if(NOT rc EQUAL 0 OR NOT n EQUAL expected)
  string(APPEND failures "\nctest lists ${n} of the ${expected} data tests as skipped (exit ${rc}):\n${out}${err}")
endif()
if(failures)
  message(FATAL_ERROR "cli.data_skip:${failures}")
endif()
message(STATUS "cli.data_skip: without a data root every data test says 'data root not found' and ctest skips it")
