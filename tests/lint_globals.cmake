# lint.globals.fixture: the writable-globals check fails on a library that keeps a setting in a
# process-wide variable, naming the symbol, and passes once the symbol is allowed.
#   cmake -DPYTHON=... -DSRC=<source root> -DCXX=<C++ compiler> -DAR=<ar> -DWORK=<scratch> -P lint_globals.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(WRITE ${WORK}/planted.cpp "namespace rayspace { namespace { int g_threads = 0; }\nvoid SetThreadCount(int n) { g_threads = n; }\nint ThreadCount() { return g_threads; }\n}\n")
execute_process(COMMAND ${CXX} -c -O1 -o ${WORK}/planted.o ${WORK}/planted.cpp RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "compiling the planted library failed")
endif()
execute_process(COMMAND ${AR} rcs ${WORK}/librayspace_planted.a ${WORK}/planted.o RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "archiving the planted library failed")
endif()
execute_process(COMMAND ${PYTHON} ${SRC}/scripts/check_globals.py --no-stale ${WORK}/librayspace_planted.a
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR NOT out MATCHES "librayspace_planted.a: writable data symbol not in the allowlist: rayspace::\\(anonymous namespace\\)::g_threads")
  message(FATAL_ERROR "the planted global was not reported (exit ${rc}):\n${out}${err}")
endif()
# Allowed by a line of its own, the same library passes; a line that matches nothing is stale.
file(WRITE ${WORK}/allow.txt "# the planted setting, allowed for this check\nlibrayspace_planted  ::g_threads$\nlibrayspace_planted  ::g_never$\n")
execute_process(COMMAND ${PYTHON} ${SRC}/scripts/check_globals.py --allowlist ${WORK}/allow.txt ${WORK}/librayspace_planted.a
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR NOT out MATCHES "allow.txt:3: matches no symbol" OR out MATCHES "g_threads")
  message(FATAL_ERROR "the stale allowlist line was not reported alone (exit ${rc}):\n${out}${err}")
endif()
execute_process(COMMAND ${PYTHON} ${SRC}/scripts/check_globals.py --no-stale --allowlist ${WORK}/allow.txt ${WORK}/librayspace_planted.a
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the allowed global was still reported (exit ${rc}):\n${out}${err}")
endif()
message(STATUS "lint.globals.fixture: planted global reported, allowed global passes, stale line reported")
