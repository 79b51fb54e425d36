# fuzz/run.sh's argument contract, run as
#   cmake -DRUN_SH=<fuzz/run.sh> -DWORK=<scratch dir> -P fuzz_run_args.cmake
# Both --harness and --seconds are required and validated before anything is built: a bad call is
# exit code 2 with one line on stderr naming the argument, at once (a harness name taken for the
# seconds used to start an endless run, a bad duration to exit 0). Every call runs under a timeout,
# since a call that gets past the checks starts a clang build.
cmake_minimum_required(VERSION 3.19)
foreach(var RUN_SH WORK)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "fuzz_run_args.cmake: pass -D${var}=...")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
# Should a call get past the checks, its build goes here, not into the source tree.
set(ENV{RAYSPACE_FUZZ_BUILD} "${WORK}/build")

set(FAILURES "")
set(CASES 0)
# bad_call(<needle> <arg>...): exit 2, one line on stderr containing the needle, nothing built.
function(bad_call needle)
  math(EXPR n "${CASES} + 1")
  set(CASES ${n} PARENT_SCOPE)
  execute_process(COMMAND bash "${RUN_SH}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                  TIMEOUT 30)
  string(REGEX MATCHALL "\n" newlines "${err}")
  list(LENGTH newlines lines)
  string(FIND "${err}" "${needle}" at)
  string(REPLACE ";" " " args "${ARGN}")
  if(NOT "${rc}" STREQUAL "2" OR NOT lines EQUAL 1 OR at EQUAL -1 OR EXISTS "${WORK}/build")
    set(FAILURES "${FAILURES}\n  [run.sh ${args}] exit code '${rc}' (expected 2), ${lines} stderr lines (expected 1), needle '${needle}'${out}\n    stderr: ${err}" PARENT_SCOPE)
    file(REMOVE_RECURSE "${WORK}/build")
  else()
    string(STRIP "${err}" line)
    message(STATUS "ok: run.sh ${args}: ${line}")
  endif()
endfunction()

bad_call("--harness is required")
bad_call("unexpected argument 'scene_load'" scene_load)
bad_call("unexpected argument '60'" 60 scene_load)
bad_call("--seconds is required" --harness scene_load)
bad_call("--harness is required" --seconds 10)
bad_call("--seconds 'scene_load'" --harness cone_grow --seconds scene_load)
bad_call("--seconds 'abc'" --harness scene_load --seconds abc)
bad_call("--seconds '0'" --harness scene_load --seconds 0)
bad_call("--seconds '-5'" --harness scene_load --seconds -5)
bad_call("--seconds '1.5'" --harness scene_load --seconds 1.5)
bad_call("--seconds '999999'" --harness scene_load --seconds 999999)
bad_call("--seconds '10s'" --harness scene_load --seconds=10s)
bad_call("--harness 'nope': unknown harness (known: " --harness nope --seconds 5)
bad_call("--harness 'nope'" --harness scene_load,nope --seconds 5)
bad_call("--seconds needs a value" --harness scene_load --seconds)
bad_call("unexpected argument '--bogus'" --harness scene_load --seconds 5 --bogus)
bad_call("--seed '0'" --harness scene_load --seconds 5 --seed 0)
bad_call("--seed 'x1'" --harness scene_load --seconds 5 --seed x1)
bad_call("--seed '4294967296'" --harness scene_load --seconds 5 --seed 4294967296)
bad_call("--seed needs a value" --harness scene_load --seconds 5 --seed)

math(EXPR CASES "${CASES} + 1")
execute_process(COMMAND bash "${RUN_SH}" --help RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 30)
if(NOT rc EQUAL 0 OR NOT out MATCHES "--harness" OR NOT out MATCHES "scene_load")
  set(FAILURES "${FAILURES}\n  [run.sh --help] exit code '${rc}', output: ${out}${err}")
endif()

if(NOT FAILURES STREQUAL "")
  message(FATAL_ERROR "fuzz.run_args: failures among ${CASES} cases:${FAILURES}")
endif()
message(STATUS "fuzz.run_args: all ${CASES} cases passed")
