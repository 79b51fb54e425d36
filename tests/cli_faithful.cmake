# The "Faithful to the thesis" switches (docs/hierarchy.md): each changes what it names and nothing
# else, --faithful is exactly its list of switches, and a bad value is refused naming the option (exit 2). Their bit-equality on both backends is
# in cli_diff.cmake (the *.faithful.* cases).
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch> -P cli_faithful.cmake
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
cli_script_begin(cli_faithful.cmake RAYSPACE SRC WORK)

# render_stats(NAME SCENE [options...]): renders SCENE at 64x64 on the emulator into WORK/NAME.png
# and WORK/NAME.json, and reads the stats into NAME_stats.
function(render_stats name scene)
  execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/${scene}.json" --size 64x64 --no-oracle --backend emu
                          --out "${WORK}/${name}.png" --stats "${WORK}/${name}.json" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "cli_faithful: render ${name} exit ${rc}: ${out}${err}")
  endif()
  file(READ "${WORK}/${name}.json" j)
  set(${name}_stats "${j}" PARENT_SCOPE)
endfunction()

# expect_equal_json(A B WHAT PATH...): the value at PATH is the same in A's and B's stats.
macro(expect_equal_json a b what)
  string(JSON _va GET "${${a}_stats}" ${ARGN})
  string(JSON _vb GET "${${b}_stats}" ${ARGN})
  if(NOT "${_va}" STREQUAL "${_vb}")
    string(APPEND FAILURES "\n${what}: ${a} has ${_va}, ${b} has ${_vb}")
  endif()
endmacro()

# --shadow-rule lit: fewer shadow rays on the office (its lamps light only some faces), the same
# image and the same reflection rays.
math(EXPR CASES "${CASES} + 1")
render_stats(all office)
render_stats(lit office --shadow-rule lit)
string(JSON all_shadow GET "${all_stats}" rays shadow total)
string(JSON lit_shadow GET "${lit_stats}" rays shadow total)
if(NOT lit_shadow LESS all_shadow)
  string(APPEND FAILURES "\n--shadow-rule lit: ${lit_shadow} shadow rays, not fewer than all's ${all_shadow}")
endif()
expect_equal_json(all lit "--shadow-rule lit: reflection rays" rays reflection total)
file(SHA256 "${WORK}/all.png" all_png)
file(SHA256 "${WORK}/lit.png" lit_png)
if(NOT all_png STREQUAL lit_png)
  string(APPEND FAILURES "\n--shadow-rule lit: the image differs from all's")
endif()

# --shadow-bounces first: the bounce-0 shadow rays and every reflection ray as before, no shadow rays
# after bounce 0 (cornell-mirrors has two bounces of mirrors).
math(EXPR CASES "${CASES} + 1")
render_stats(every cornell-mirrors)
render_stats(first cornell-mirrors --shadow-bounces first)
expect_equal_json(every first "--shadow-bounces first: bounce-0 shadow rays" rays shadow per_bounce 0 rays)
expect_equal_json(every first "--shadow-bounces first: reflection rays" rays reflection total)
string(JSON first_shadow GET "${first_stats}" rays shadow total)
string(JSON first_b0 GET "${first_stats}" rays shadow per_bounce 0 rays)
string(JSON every_shadow GET "${every_stats}" rays shadow total)
if(NOT first_shadow EQUAL first_b0 OR NOT first_shadow LESS every_shadow)
  string(APPEND FAILURES "\n--shadow-bounces first: ${first_shadow} shadow rays, expected bounce 0's ${first_b0} (all: ${every_shadow})")
endif()

# --one-object: the office's objects merged into one (fewer object-sphere tests), the same rays and image.
math(EXPR CASES "${CASES} + 1")
render_stats(one office --one-object)
expect_equal_json(all one "--one-object: rays" rays)
string(JSON one_tests GET "${one_stats}" object_sphere_tests)
string(JSON many_tests GET "${all_stats}" object_sphere_tests)
if(NOT one_tests LESS many_tests)
  string(APPEND FAILURES "\n--one-object: ${one_tests} object-sphere tests, not fewer than ${many_tests}")
endif()
file(SHA256 "${WORK}/one.png" one_png)
if(NOT one_png STREQUAL all_png)
  string(APPEND FAILURES "\n--one-object: the image differs")
endif()

# --cone-test printed: the same rays, other pairs kept by the traversal (it traces --objects flat, so
# against the conservative test on flat objects).
math(EXPR CASES "${CASES} + 1")
render_stats(flat cornell-mirrors --objects flat)
render_stats(printed cornell-mirrors --cone-test printed)
expect_equal_json(flat printed "--cone-test printed: rays" rays)
string(JSON flat_tests GET "${flat_stats}" total_tests)
string(JSON printed_tests GET "${printed_stats}" total_tests)
if(flat_tests EQUAL printed_tests)
  string(APPEND FAILURES "\n--cone-test printed: ${printed_tests} tests, as many as the conservative test's")
endif()
# printed-signed: one cone, not two apex to apex: fewer pairs kept than the printed test's.
render_stats(signed cornell-mirrors --cone-test printed-signed)
expect_equal_json(flat signed "--cone-test printed-signed: rays" rays)
string(JSON signed_tests GET "${signed_stats}" total_tests)
if(NOT signed_tests LESS printed_tests)
  string(APPEND FAILURES "\n--cone-test printed-signed: ${signed_tests} tests, not fewer than the printed test's ${printed_tests}")
endif()

# --faithful thesis: the same frame as its switches given one by one (the preset is only a list of
# switches), and a switch given beside it wins over the preset's value.
math(EXPR CASES "${CASES} + 1")
set(thesis_switches --shadow-bounces first --objects flat --child-merge pairwise)
render_stats(preset cornell-mirrors --faithful thesis)
render_stats(spelled cornell-mirrors ${thesis_switches})
render_stats(preset10 cornell-mirrors --faithful thesis --shadow-bounces all)
render_stats(spelled10 cornell-mirrors --shadow-bounces all --objects flat --child-merge pairwise)
foreach(path "total_tests" "rays;shadow;total" "rays;reflection;total" "object_sphere_tests")
  expect_equal_json(preset spelled "--faithful thesis: ${path}" ${path})
  expect_equal_json(preset10 spelled10 "--faithful thesis --shadow-bounces all: ${path}" ${path})
endforeach()
string(JSON preset_total GET "${preset_stats}" total_tests)
string(JSON preset10_total GET "${preset10_stats}" total_tests)
string(JSON every_total GET "${every_stats}" total_tests)
if(preset_total EQUAL preset10_total OR preset_total EQUAL every_total)
  string(APPEND FAILURES "\n--faithful thesis: ${preset_total} tests, the same as with --shadow-bounces all (${preset10_total}) "
                         "or without the preset (${every_total}): the preset changes nothing here")
endif()
foreach(img preset spelled)
  file(SHA256 "${WORK}/${img}.png" ${img}_png)
endforeach()
if(NOT preset_png STREQUAL spelled_png)
  string(APPEND FAILURES "\n--faithful thesis: the image differs from its switches'")
endif()

# Bad values: one line naming the option, exit 2, on every command that takes it.
foreach(bad "render;--faithful;rogers" "diff;--faithful;Thesis" "render;--shadow-rule;some" "diff;--shadow-rule;some"
            "render;--shadow-bounces;2" "diff;--shadow-bounces;2" "render;--cone-test;exact" "diff;--cone-test;exact"
            "render;--cone-test;printed;--objects;tree")
  list(GET bad 0 cmd)
  list(SUBLIST bad 1 -1 opt)
  math(EXPR CASES "${CASES} + 1")
  execute_process(COMMAND "${RAYSPACE}" ${cmd} "${SRC}/scenes/cornell-mirrors.json" ${opt}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  list(GET opt 0 name)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "${name}")
    string(APPEND FAILURES "\n${cmd} ${opt}: exit ${rc}, expected 2 with a line naming ${name}: ${err}")
  endif()
endforeach()
math(EXPR CASES "${CASES} + 1")
execute_process(COMMAND "${RAYSPACE}" bench "${SRC}/scenes/cornell-mirrors.json" --shadow-rule some
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--shadow-rule")
  string(APPEND FAILURES "\nbench --shadow-rule some: exit ${rc}, expected 2 naming --shadow-rule: ${err}")
endif()
# bench: a named object-tree configuration is refused under --cone-test printed before the first frame.
math(EXPR CASES "${CASES} + 1")
execute_process(COMMAND "${RAYSPACE}" bench "${SRC}/scenes/cornell-mirrors.json" --cone-test printed --configs crsh-tree
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--cone-test printed: configuration 'crsh-tree'")
  string(APPEND FAILURES "\nbench --cone-test printed --configs crsh-tree: exit ${rc}, expected 2 naming the configuration: ${err}")
endif()

cli_script_end(cli_faithful)
