# The hierarchy's statistics through the CLI at reduced sizes (the full-size runs are in
# docs/performance.md): the thesis's trends, the RAH top-level count, the accounting identity in
# every stats file and zero oracle mismatches.
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DDATA=<data root> -DWORK=<scratch> [-DPART=sponza] -P cli_hierarchy.cmake
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
set(failures "")
file(MAKE_DIRECTORY "${WORK}")

# Extra arguments after `depth` go to render as they are (--objects tree).
function(render name scene size algo depth)
  execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/${scene}.json" --data "${DATA}" --size ${size}
                          --algo ${algo} --depth ${depth} ${ARGN} --out "${WORK}/${name}.png" --stats "${WORK}/${name}.json"
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: exit ${rc}: ${err}")
  endif()
  file(READ "${WORK}/${name}.json" j)
  string(JSON mism GET "${j}" oracle mismatches)
  if(NOT mism EQUAL 0)
    message(FATAL_ERROR "${name}: ${mism} oracle mismatches")
  endif()
  string(JSON total GET "${j}" total_tests)
  # Identity: total = every level's intersections + every type's final tests + the rays' own tests
  # (--objects tree; 0 otherwise).
  string(JSON sum ERROR_VARIABLE no_tree GET "${j}" object_tree rays intersections)
  if(no_tree)
    set(sum 0)
  endif()
  string(JSON nlev LENGTH "${j}" levels)
  if(nlev GREATER 0)
    math(EXPR last "${nlev} - 1")
    foreach(i RANGE ${last})
      string(JSON v GET "${j}" levels ${i} intersections)
      math(EXPR sum "${sum} + ${v}")
    endforeach()
  endif()
  string(JSON ntypes LENGTH "${j}" final_tests)
  math(EXPR last "${ntypes} - 1")
  foreach(i RANGE ${last})
    string(JSON key MEMBER "${j}" final_tests ${i})
    string(JSON v GET "${j}" final_tests ${key})
    math(EXPR sum "${sum} + ${v}")
  endforeach()
  if(NOT sum EQUAL total)
    message(FATAL_ERROR "${name}: total_tests ${total} != levels + final tests ${sum}")
  endif()
  # Top-level shadow intersections (level == depth).
  set(top 0)
  if(nlev GREATER 0)
    math(EXPR last "${nlev} - 1")
    foreach(i RANGE ${last})
      string(JSON lvl GET "${j}" levels ${i} level)
      string(JSON ty GET "${j}" levels ${i} ray_type)
      if(lvl EQUAL depth AND ty STREQUAL "shadow")
        string(JSON top GET "${j}" levels ${i} intersections)
      endif()
    endforeach()
  endif()
  string(JSON brute GET "${j}" brute_force_tests)
  string(JSON tris GET "${j}" triangles)
  string(JSON rays GET "${j}" rays shadow total)
  set(${name}_total ${total} PARENT_SCOPE)
  set(${name}_top ${top} PARENT_SCOPE)
  set(${name}_brute ${brute} PARENT_SCOPE)
  set(${name}_tris ${tris} PARENT_SCOPE)
  set(${name}_rays ${rays} PARENT_SCOPE)
  string(JSON tree ERROR_VARIABLE no_tree GET "${j}" object_tree rounds)
  if(no_tree)
    set(tree 0)
  endif()
  set(${name}_tree ${tree} PARENT_SCOPE)
  file(SHA256 "${WORK}/${name}.png" png)
  set(${name}_png ${png} PARENT_SCOPE)
endfunction()

macro(expect a op b msg)
  if(NOT ${a} ${op} ${b})
    list(APPEND failures "${msg}")
  endif()
endmacro()

# PART=sponza: only the Sponza cases (test cli.hierarchy.sponza), which need the data root; without
# it they print "data root not found" and ctest counts them as skipped (SKIP_REGULAR_EXPRESSION).
if(PART STREQUAL "sponza")
  cli_require_data(cli.hierarchy.sponza)
  render(sponza_crsh sponza 128x128 crsh 2 --objects flat)
  render(sponza_rah sponza 128x128 rah 2 --objects flat)
  render(sponza_crsh3 sponza 128x128 crsh 3 --objects flat)
  math(EXPR rah_top "(${sponza_rah_rays} + 63) / 64 * ${sponza_rah_tris}")
  expect(${sponza_rah_top} EQUAL ${rah_top} "sponza: RAH top level ${sponza_rah_top} != ceil(rays/64) x triangles ${rah_top}")
  expect(${sponza_crsh_total} LESS ${sponza_rah_total} "sponza: CRSH total ${sponza_crsh_total} not below RAH ${sponza_rah_total}")
  expect(${sponza_rah_total} LESS ${sponza_rah_brute} "sponza: RAH total not below brute force")
  expect(${sponza_crsh3_total} LESS ${sponza_crsh_total} "sponza: CRSH depth 3 ${sponza_crsh3_total} not below depth 2 ${sponza_crsh_total}")
  if(failures)
    list(JOIN failures "\n" text)
    message(FATAL_ERROR "${text}")
  endif()
  return()
endif()

# CMake's math() is 64-bit, enough for these counts. The thesis's trends are flat's (the thesis counts
# every triangle of every object a top node may meet).
render(cornell_crsh cornell-mirrors 96x96 crsh 2 --objects flat)
render(cornell_rah cornell-mirrors 96x96 rah 2 --objects flat)
expect(${cornell_crsh_total} LESS ${cornell_rah_total} "cornell: CRSH total ${cornell_crsh_total} not below RAH ${cornell_rah_total}")

render(office_crsh office 96x96 crsh 2 --objects flat)
render(office_rah office 96x96 rah 2 --objects flat)
expect(${office_crsh_top} LESS ${office_rah_top} "office: CRSH top level ${office_crsh_top} not below RAH ${office_rah_top}")

# --objects tree: the same image, the joint descent's rounds reported, its rays' tests in the total,
# fewer top-level and total tests than flat.
render(office_tree office 96x96 crsh 2 --objects tree)
expect("${office_tree_png}" STREQUAL "${office_crsh_png}" "office: --objects tree gave another image than flat")
expect(${office_tree_tree} GREATER 0 "office: --objects tree reported no rounds of the joint descent")
expect(${office_crsh_tree} EQUAL 0 "office: flat reported rounds of the joint descent")
expect(${office_tree_top} LESS ${office_crsh_top} "office: tree top level ${office_tree_top} not below flat ${office_crsh_top}")
expect(${office_tree_total} LESS ${office_crsh_total} "office: tree total ${office_tree_total} not below flat ${office_crsh_total}")

# --objects auto (render's default): per batch, recorded in the stats; the same image as flat.
render(cornell_auto cornell-mirrors 96x96 crsh 2)
expect("${cornell_auto_png}" STREQUAL "${cornell_crsh_png}" "cornell: --objects auto gave another image than flat")


if(failures)
  list(JOIN failures "\n" text)
  message(FATAL_ERROR "${text}")
endif()
message(STATUS "hierarchy statistics: all checks passed")
