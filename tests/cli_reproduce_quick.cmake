# `rayspace reproduce thesis roger --quick`, whole (the thesis's 75 configurations and roger's, at 128x128): every table of 4.1-4.24
# has its section, CSV and plot, and every relation the thesis states is judged on both sides with
# no relation left without a verdict. The counts themselves are the report's, not this test's: it
# checks that the sweep runs end to end and says something about each relation.
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DDATA=<data root> -DWORK=<scratch> -P cli_reproduce_quick.cmake
cmake_minimum_required(VERSION 3.19)
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
cli_require_data(cli.reproduce.quick bunny/bun_zipper_res4.ply bunny/bun_zipper_res3.ply)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
execute_process(COMMAND "${RAYSPACE}" reproduce thesis roger --quick --scenes "${SRC}/scenes" --data "${DATA}" --out quick
                WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 900)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cli.reproduce.quick: exit ${rc}:\n${out}${err}")
endif()
set(FAILURES "")
file(READ "${WORK}/quick/report.md" report)
foreach(n RANGE 1 24)
  if(n LESS 10)
    set(id "4.0${n}")
  else()
    set(id "4.${n}")
  endif()
  string(FIND "${report}" "## Table 4.${n}:" at)
  if(at EQUAL -1 OR NOT EXISTS "${WORK}/quick/tables/table-${id}.csv" OR NOT EXISTS "${WORK}/quick/plots/table-${id}.svg")
    set(FAILURES "${FAILURES}\n  table 4.${n}: section, CSV or plot missing")
  endif()
endforeach()
# The summary: each relation with its source (the thesis's section) or the project's reason, and
# "k of n" on both sides, n > 0.
foreach(relation "CRSH total < RAH total" "RAH top level = top nodes x triangles"
                 "total = sum of level intersections + level-1 hits x subdivision" "total < brute force"
                 "CRSH total > the baseline's \\(s8 d2\\)" "CRSH total < the baseline's \\(s8 d2\\)"
                 "CRSH depth 4 total < depth 3 total" "CRSH depth 4 total > depth 3 total")
  string(REPLACE "+" "\\+" pattern "${relation}")
  string(REGEX MATCH "\\| ${pattern} \\| [^|\n]+ \\| [0-9]+ of [1-9][0-9]* \\| [0-9]+ of [1-9][0-9]* \\|" row "${report}")
  if(row STREQUAL "")
    set(FAILURES "${FAILURES}\n  relation '${relation}' has no verdict on both sides in the summary")
  endif()
endforeach()
# roger: every claim judged (holds or fails) in its summary, each figure with its CSV.
foreach(claim "grows with the bunny's polygons" "grows with n of cos" "between 2.5 and 4.5" "less than 4x the cone-sphere tests"
              "grows faster with the scene's polygons" "loose upper levels do not slow" "more than double the frame")
  string(REGEX MATCH "\\| [^|\n]*${claim}[^|\n]* \\| [^|\n]+ \\| (holds|fails) \\|" row "${report}")
  if(row STREQUAL "")
    set(FAILURES "${FAILURES}\n  roger claim '${claim}' has no verdict in the summary")
  endif()
endforeach()
foreach(id roger-summary roger-9a roger-9b roger-9c roger-10 roger-12 roger-museum roger-13a roger-13c)
  if(NOT EXISTS "${WORK}/quick/tables/table-${id}.csv")
    set(FAILURES "${FAILURES}\n  no tables/table-${id}.csv")
  endif()
endforeach()
if(NOT FAILURES STREQUAL "")
  message(FATAL_ERROR "cli.reproduce.quick: failures:${FAILURES}")
endif()
message(STATUS "cli.reproduce.quick: 24 tables with CSV and plot, every relation judged")
