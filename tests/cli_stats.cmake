# The statistics a user reads, on a scene whose counts follow by hand, run as
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch dir> -P cli_stats.cmake
# The camera sits inside a 12-triangle box whose walls are mirrors, at 4x4 with one light and one
# bounce: every pixel hits a wall, so 16 shadow rays at bounce 0, 16 reflection rays and their 16
# shadow rays at bounce 1. Brute force per type = rays of the type x 12: shadow 32 x 12 = 384,
# reflection 16 x 12 = 192, the frame 576. The thesis's per-type shares divide by the type's own.
cmake_minimum_required(VERSION 3.19)  # string(JSON)
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
cli_script_begin(cli_stats.cmake RAYSPACE SRC WORK)
file(WRITE "${WORK}/box.json" [=[
{"camera": {"eye": [0, 0, 0], "target": [0, 0, 1], "up": [0, 1, 0], "fov_y_deg": 60},
 "image": {"width": 4, "height": 4},
 "lights": [{"position": [0, 3, 0]}],
 "materials": {"mirror": {"diffuse": [0.5, 0.5, 0.5], "reflectivity": 0.5}},
 "objects": [{"generator": "box", "params": {"size": 10, "inward": true}, "material": "mirror"}],
 "max_depth": 1}
]=])

function(check what got want)
  if(NOT "${got}" STREQUAL "${want}")
    set(FAILURES "${FAILURES}\n  ${what}: ${got}, expected ${want}" PARENT_SCOPE)
  endif()
endfunction()

# Percent to two places as printf rounds it (ties aside): 100 * part / whole.
function(percent out part whole)
  if(NOT part MATCHES "^[0-9]+$")
    set(${out} "(no count: ${part})" PARENT_SCOPE)
    return()
  endif()
  math(EXPR bp "(${part} * 20000 + ${whole}) / (2 * ${whole})")
  math(EXPR int "${bp} / 100")
  math(EXPR frac "${bp} % 100")
  if(frac LESS 10)
    set(frac "0${frac}")
  endif()
  set(${out} "${int}.${frac}%" PARENT_SCOPE)
endfunction()

foreach(algo crsh brute)
  execute_process(COMMAND "${RAYSPACE}" render "${WORK}/box.json" --algo ${algo} --objects flat --out "${WORK}/${algo}.png"
                          --stats "${WORK}/${algo}.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "render --algo ${algo}: exit ${rc}: ${err}")
  endif()
  file(READ "${WORK}/${algo}.json" stats)
  string(JSON frame_bf ERROR_VARIABLE jerr GET "${stats}" brute_force_tests)
  check("${algo}: frame brute force" "${frame_bf}" 576)
  foreach(type_bf shadow:32:384 reflection:16:192)
    string(REPLACE ":" ";" type_bf "${type_bf}")
    list(GET type_bf 0 type)
    list(GET type_bf 1 rays)
    list(GET type_bf 2 bf)
    string(JSON got_rays ERROR_VARIABLE jerr GET "${stats}" per_type ${type} rays)
    string(JSON got_bf ERROR_VARIABLE jerr GET "${stats}" per_type ${type} brute_force_tests)
    string(JSON got_total ERROR_VARIABLE jerr GET "${stats}" per_type ${type} total_tests)
    check("${algo}: ${type} rays" "${got_rays}" ${rays})
    check("${algo}: ${type} brute force" "${got_bf}" ${bf})
    percent(own "${got_total}" ${bf})
    string(FIND "${out}" "tests ${got_total} (${own} of its brute force ${bf} = ${rays} rays x 12 triangles)" at)
    if(at EQUAL -1)
      set(FAILURES "${FAILURES}\n  ${algo}: the summary does not give ${type}'s tests as ${own} of its brute force ${bf}")
    endif()
  endforeach()
  if(algo STREQUAL "crsh")
    # The table's per-level share: the shadow rays' top level against the shadow brute force (384),
    # and the old figure against the frame's (576) on its own, labelled row.
    string(JSON top_type ERROR_VARIABLE jerr GET "${stats}" levels 0 ray_type)
    string(JSON top_level ERROR_VARIABLE jerr GET "${stats}" levels 0 level)
    check("levels[0]" "${top_type} ${top_level}" "shadow 2")
    string(JSON sh_top ERROR_VARIABLE jerr GET "${stats}" levels 0 intersections)
    percent(own "${sh_top}" 384)
    percent(frame "${sh_top}" 576)
    if(NOT out MATCHES "# SH % OF BRUTE FORCE +${own} ")
      set(FAILURES "${FAILURES}\n  the shadow level-2 share is not ${own} (${sh_top} of 384):\n${out}")
    endif()
    if(NOT out MATCHES "# SH % OF FRAME BF +${frame} ")
      set(FAILURES "${FAILURES}\n  the shadow level-2 share of the frame is not ${frame} (${sh_top} of 576)")
    endif()
  endif()
  # What made the file: the version and the arguments as given.
  string(JSON version ERROR_VARIABLE jerr GET "${stats}" rayspace_version)
  if(jerr OR NOT version MATCHES "^[0-9]+\\.[0-9]+\\.[0-9]+$")
    set(FAILURES "${FAILURES}\n  ${algo}: rayspace_version '${version}' (${jerr})")
  endif()
  string(JSON arg4 ERROR_VARIABLE jerr GET "${stats}" arguments 4)
  string(JSON nargs ERROR_VARIABLE jerr LENGTH "${stats}" arguments)
  check("${algo}: arguments[4]" "${arg4}" ${algo})
  check("${algo}: arguments" "${nargs}" 11)
endforeach()

# A level's share below 1 % keeps three significant digits (69K triangles give shares of 0.0003 %,
# which two decimals would print as 0.00 %): the Cornell box's top level at 64x64 with three levels
# is about 0.2 % of the shadow brute force, printed as 0.xyz %.
execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 64x64 --levels 3 --objects flat
                        --out "${WORK}/cornell.png" --stats "${WORK}/cornell.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(REGEX MATCH "# SH % OF BRUTE FORCE[^\n]*" row "${out}")
if(NOT rc EQUAL 0 OR NOT row MATCHES "OF BRUTE FORCE +0\\.[0-9][0-9][0-9]% ")
  set(FAILURES "${FAILURES}\n  a share under 1 %: exit ${rc}, row '${row}' (expected three significant digits)${err}")
endif()
# The table's count rows, top level first, are the statistics' own: here levels miss, so
# intersections, misses and hits all differ.
if(EXISTS "${WORK}/cornell.json")
  file(READ "${WORK}/cornell.json" stats)
  foreach(field intersections misses hits)
    set(want_${field} "")
  endforeach()
  foreach(i RANGE 2)
    string(JSON type ERROR_VARIABLE jerr GET "${stats}" levels ${i} ray_type)
    foreach(field intersections misses hits)
      string(JSON v ERROR_VARIABLE jerr GET "${stats}" levels ${i} ${field})
      string(APPEND want_${field} " +${v}")
    endforeach()
    check("levels[${i}] type" "${type}" "shadow")
  endforeach()
  foreach(field intersections misses hits)
    string(TOUPPER "${field}" label)
    if(NOT out MATCHES "# SH ${label}${want_${field}}\n")
      set(FAILURES "${FAILURES}\n  the ${label} row is not the statistics' (${want_${field}}):\n${out}")
    endif()
  endforeach()
endif()

# Embree's BVH reports no tests: no count and no throughput are made up from the brute force.
execute_process(COMMAND "${RAYSPACE}" render "${WORK}/box.json" --algo embree --timings --out "${WORK}/embree.png"
                        --stats "${WORK}/embree.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
file(READ "${WORK}/embree.json" stats)
string(JSON total_type ERROR_VARIABLE jerr TYPE "${stats}" total_tests)
# Per ray type too: its brute force stays, its tests and shares are not made up.
string(JSON type_total ERROR_VARIABLE jerr2 TYPE "${stats}" per_type shadow total_tests)
string(JSON type_share ERROR_VARIABLE jerr3 TYPE "${stats}" per_type shadow percent_of_brute_force)
string(JSON type_bf ERROR_VARIABLE jerr4 GET "${stats}" per_type shadow brute_force_tests)
if(NOT rc EQUAL 0 OR NOT out MATCHES "total tests +not counted \\(Embree's BVH does not report its tests; brute force 576\\)"
   OR NOT out MATCHES "throughput +n/a" OR out MATCHES "M tests/s" OR NOT total_type STREQUAL "NULL"
   OR NOT type_total STREQUAL "NULL" OR NOT type_share STREQUAL "NULL" OR NOT type_bf GREATER 0)
  set(FAILURES "${FAILURES}\n  embree: exit ${rc}, total_tests ${total_type}, per_type.shadow total_tests ${type_total} "
      "percent_of_brute_force ${type_share} brute_force_tests ${type_bf}; stdout: ${out}${err}")
endif()

if(FAILURES)
  message(FATAL_ERROR "cli.stats:${FAILURES}")
endif()
message(STATUS "cli.stats: per-type brute force 384 and 192 of 576, shares of each type's own, version and arguments recorded")
