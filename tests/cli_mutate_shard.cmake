# `mutate --shard I/N` and `mutate merge`: two shards (run with different --jobs) of three items (two
# mutants and a variant), merged, give the report of one run byte for byte, and a valid JUnit file;
# merging one of the two, or a shard twice, is refused (exit 2) naming the file; --shard out of range
# is refused.
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DXMLLINT=<xmllint> -DWORK=<scratch> -P cli_mutate_shard.cmake
cmake_minimum_required(VERSION 3.19)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(failures "")
set(run mutate "${SRC}/scenes/cornell-mirrors.json" --config crsh --size 16x16 --limit 2 --variants 1 --pass trim --timeout 60)

function(mutate name)
  execute_process(COMMAND "${RAYSPACE}" ${run} --report "${WORK}/${name}.json" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err TIMEOUT 600)
  if(NOT rc EQUAL 0)
    set(failures "${failures}\n${name}: exit ${rc}: ${out}${err}" PARENT_SCOPE)
  endif()
endfunction()

mutate(one)
mutate(shard0 --shard 0/2)
mutate(shard1 --shard 1/2 --jobs 2)
execute_process(COMMAND "${RAYSPACE}" mutate merge "${WORK}/merged.json" "${WORK}/shard1.json" "${WORK}/shard0.json"
                        --junit "${WORK}/merged.xml"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  string(APPEND failures "\nmerge: exit ${rc}: ${out}${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${WORK}/one.json" "${WORK}/merged.json" RESULT_VARIABLE differ)
if(differ)
  string(APPEND failures "\nthe merged report differs from one run's (diff ${WORK}/one.json ${WORK}/merged.json)")
endif()
file(READ "${WORK}/one.json" one)
string(JSON n LENGTH "${one}" mutants)
string(JSON v LENGTH "${one}" variants)
if(NOT n EQUAL 2 OR NOT v EQUAL 1)
  string(APPEND failures "\none run: ${n} mutants and ${v} variants, expected 2 and 1")
endif()
execute_process(COMMAND "${XMLLINT}" --noout --schema "${SRC}/docs/schemas/junit.xsd" "${WORK}/merged.xml" RESULT_VARIABLE valid
                ERROR_VARIABLE why)
if(NOT valid EQUAL 0)
  string(APPEND failures "\nmerged.xml: not valid under junit.xsd: ${why}")
endif()

# refused(NAME REGEX ARGS...): exit 2 with stderr matching REGEX.
function(refused name regex)
  execute_process(COMMAND "${RAYSPACE}" ${ARGN} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "${regex}")
    set(failures "${failures}\n${name}: exit ${rc}, stderr '${err}'" PARENT_SCOPE)
  endif()
endfunction()
refused(missing "1 of the run's 2 shards" mutate merge "${WORK}/m.json" "${WORK}/shard1.json")
refused(twice "shard1.json: shard 1/2 out of range or given twice" mutate merge "${WORK}/m.json" "${WORK}/shard0.json"
        "${WORK}/shard1.json" "${WORK}/shard1.json")
refused(not_shard "one.json: not the report of a rayspace mutate --shard run" mutate merge "${WORK}/m.json" "${WORK}/one.json")
refused(range "--shard '2/2': needs 0 <= I < N" ${run} --shard 2/2)
if(EXISTS "${WORK}/m.json")
  string(APPEND failures "\na refused merge left m.json")
endif()

if(failures)
  message(FATAL_ERROR "cli.mutate.shard:${failures}")
endif()
message(STATUS "cli.mutate.shard: three shards merged equal one run, byte for byte")
