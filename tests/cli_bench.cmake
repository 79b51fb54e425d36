# `rayspace bench`: one run prints the table with a row per configuration, the configurations of one
# tracer give one digest, the JSON file holds every measurement, and a configuration whose backend
# cannot run here is a "skipped" row, not a failure. (Its bad inputs are in cli_errors.cmake.)
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch> -DVULKAN=<ON|OFF> -P cli_bench.cmake
cmake_minimum_required(VERSION 3.19)  # string(JSON)
set(failures "")
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(cornell "${SRC}/scenes/cornell-mirrors.json")

# Adds `why` to the failures when `text` does not match `regex`.
function(expect_match text regex why)
  if(NOT text MATCHES "${regex}")
    set(failures "${failures}\n${why}" PARENT_SCOPE)
  endif()
endfunction()

execute_process(COMMAND "${RAYSPACE}" bench "${cornell}" --sizes 64x64 --repetitions 1 --configs embree,crsh-passes,crsh
                        --json "${WORK}/bench.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "bench: exit ${rc}, expected 0:\n${out}${err}")
endif()
expect_match("${out}" "\nscene +size +config +median ms +min-max ms +x embree +total tests +M tests/s +peak MB +MB added +digest\n"
             "no table header")
foreach(config embree crsh-passes crsh)
  # scene, size, config, median, min-max, ratio, tests (n/a for embree, which counts none), tests/s (n/a for
  # embree), peak, added, digest
  expect_match("${out}" "\ncornell-mirrors +64x64 +${config} +[0-9.]+ +[0-9.]+-[0-9.]+ +[0-9.]+ +([0-9,]+|n/a) +([0-9.]+|n/a) +[0-9.]+ +[-+][0-9.]+ +[0-9a-f]+\n"
               "no table row for ${config}")
endforeach()
expect_match("${out}" "\ncornell-mirrors +64x64 +embree +[0-9.]+ +[0-9.-]+ +1.00 +n/a +n/a " "embree's ratio to itself is not 1.00, or it shows tests it does not count")
expect_match("${out}" "\ncrsh-passes and crsh: one digest per scene and size" "no line saying crsh-passes and crsh agree")

file(READ "${WORK}/bench.json" j)
string(JSON n LENGTH "${j}" results)
if(NOT n EQUAL 3)
  set(failures "${failures}\nJSON: ${n} results, expected 3")
else()
  string(JSON passes GET "${j}" results 1 digests 0)
  string(JSON fused GET "${j}" results 2 digests 0)
  string(JSON config GET "${j}" results 1 config)
  string(JSON width GET "${j}" results 2 width)
  string(JSON peak GET "${j}" results 2 peak_rss_bytes)
  if(NOT config STREQUAL "crsh-passes" OR NOT width EQUAL 64 OR peak LESS 1000000)
    set(failures "${failures}\nJSON: results[1].config '${config}', results[2].width ${width}, peak_rss_bytes ${peak}")
  endif()
  if(NOT passes STREQUAL fused)
    set(failures "${failures}\nJSON: crsh-passes digest ${passes}, crsh ${fused}")
  endif()
endif()

# Two sizes: the growth table, with the search and the traversal alone for crsh, "-" for embree
# (which does not split its tracing into traversal and final tests).
execute_process(COMMAND "${RAYSPACE}" bench "${cornell}" --sizes 32x32,64x64 --repetitions 1 --configs embree,crsh
                --json "${WORK}/growth.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out2 ERROR_VARIABLE err TIMEOUT 300)
if(NOT rc EQUAL 0)
  set(failures "${failures}\nbench at two sizes: exit ${rc}, expected 0:\n${out2}${err}")
endif()
expect_match("${out2}" "\nscene +config +sizes +pixels +frame +search +traversal\n" "no growth table header:\n${out2}")
expect_match("${out2}" "\ncornell-mirrors +crsh +32x32 -> 64x64 +x4 +x[0-9.]+ +x[0-9.]+ +x[0-9.]+\n"
             "no growth row for crsh with its search and traversal")
expect_match("${out2}" "\ncornell-mirrors +embree +32x32 -> 64x64 +x4 +x[0-9.]+ +- +-\n"
             "embree's growth row does not leave search and traversal out")
file(READ "${WORK}/growth.json" j2)
string(JSON trav ERROR_VARIABLE jerr GET "${j2}" results 3 traversal_ms 0)
string(JSON search ERROR_VARIABLE jerr2 GET "${j2}" results 3 search_ms 0)
if(jerr OR jerr2 OR NOT trav GREATER 0 OR trav GREATER search)
  set(failures "${failures}\nJSON: crsh at 64x64 traversal_ms ${trav} (${jerr}), search_ms ${search}: expected 0 < traversal <= search")
endif()

# The Vulkan configuration on a device that lacks a requirement (or a build without Vulkan): skipped.
set(lacks "")
if(VULKAN)
  set(lacks --device-lacks shaderInt64)
endif()
execute_process(COMMAND "${RAYSPACE}" bench "${cornell}" --sizes 16x16 --repetitions 1 --configs crsh,vulkan ${lacks}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
if(NOT rc EQUAL 0 OR NOT out MATCHES "\ncornell-mirrors +16x16 +vulkan +skipped: [^\n]+\n")
  set(failures "${failures}\nvulkan without a usable device: exit ${rc}, expected 0 and a skipped row:\n${out}${err}")
endif()

if(failures)
  message(FATAL_ERROR "cli.bench:${failures}\nstdout of the first run:\n${out}")
endif()
message(STATUS "cli.bench: table, digests, JSON and the skipped row as expected")
