# SIGTERM in the middle of writing leaves nothing half-done: `export` (its partial directory half
# filled) and `reproduce` (a result file written, not yet renamed into place). Each run is stopped
# at a known moment by RAYSPACE_TEST_SIGTERM=POINT:N (core output_file.h, TestSignalPoint), which
# raises SIGTERM there, so the test never races the run. Afterwards: the run died by the signal,
# no output is partial, nothing is left under TMPDIR, and the same command (reproduce: --resume)
# completes. `diff --save-inputs` has its own case (cli.diff.save-inputs.sigterm).
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch> -P cli_sigterm.cmake
cmake_minimum_required(VERSION 3.19)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/tmp")
set(FAILURES "")
set(ENV{TMPDIR} "${WORK}/tmp")

# Runs ARGN with RAYSPACE_TEST_SIGTERM=POINT; a run the signal ended exits 143 through the shell.
function(stopped_at point)
  execute_process(COMMAND env RAYSPACE_TEST_SIGTERM=${point} sh -c "\"$0\" \"$@\"; echo \"exit $?\" >&2" ${ARGN}
                  WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT err MATCHES "exit 143\n$")
    set(FAILURES "${FAILURES}\n${point}: not ended by SIGTERM: ${out}${err}" PARENT_SCOPE)
  endif()
endfunction()

# Nothing left under TMPDIR, polled for up to 10 s (the forked cleaner runs once the process is gone).
function(tmpdir_empty what)
  foreach(i RANGE 50)
    file(GLOB left "${WORK}/tmp/*" "${WORK}/tmp/.*")
    if(NOT left)
      return()
    endif()
    execute_process(COMMAND sleep 0.2)
  endforeach()
  set(FAILURES "${FAILURES}\n${what}: left under TMPDIR: ${left}" PARENT_SCOPE)
endfunction()

# export: a saved call of a small diff, exported with SIGTERM after its third file.
execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --save-inputs "${WORK}/saved"
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
file(GLOB calls "${WORK}/saved/*-reduce.*")
if(NOT rc EQUAL 0 OR NOT calls)
  message(FATAL_ERROR "diff --save-inputs: exit ${rc}, no reduce call saved: ${err}")
endif()
list(GET calls 0 call)
stopped_at(export.file:3 "${RAYSPACE}" export "${call}" --out "${WORK}/export")
file(GLOB partial "${WORK}/export*")
if(partial)
  set(FAILURES "${FAILURES}\nexport: left behind: ${partial}")
endif()
tmpdir_empty(export)
execute_process(COMMAND "${RAYSPACE}" export "${call}" --out "${WORK}/export" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS "${WORK}/export/repro.c")
  set(FAILURES "${FAILURES}\nexport: the rerun: exit ${rc}: ${err}")
endif()

# reproduce: run.json and the first result published, SIGTERM as the second result is renamed.
set(repro reproduce thesis --size 16x16 --only "^(OFFICE|CORNELL) crsh s8 d2$" --scenes "${SRC}/scenes" --out "${WORK}/repro")
stopped_at(publish:3 "${RAYSPACE}" ${repro})
file(GLOB_RECURSE kept RELATIVE "${WORK}/repro" "${WORK}/repro/*")
list(LENGTH kept n)
set(complete TRUE)
foreach(f ${kept})
  if(NOT f MATCHES "^(run\\.json|results/[0-9a-f]+\\.json)$")
    set(complete FALSE)
  endif()
endforeach()
if(NOT n EQUAL 2 OR NOT complete)
  set(FAILURES "${FAILURES}\nreproduce: expected run.json and one result, found: ${kept}")
endif()
tmpdir_empty(reproduce)
execute_process(COMMAND "${RAYSPACE}" ${repro} --resume WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "2 configurations \\(1 measured now\\)" OR NOT EXISTS "${WORK}/repro/report.md")
  set(FAILURES "${FAILURES}\nreproduce --resume: exit ${rc}: ${out}${err}")
endif()

if(FAILURES)
  message(FATAL_ERROR "cli_sigterm:${FAILURES}")
endif()
