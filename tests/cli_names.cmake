# Names and defaults on the command line, run as
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch dir> -DVULKAN=ON|OFF -P cli_names.cmake
# --levels (hierarchy levels; --depth its older name) and --bounces (the scene's max_depth) are
# distinct and the summary names both; --help shows each default; a flag the chosen mode does not use
# draws one warning line; --pair-capacity below its real minimum and --device beyond the devices are
# refused naming what would do; a mismatch names the backends.
cmake_minimum_required(VERSION 3.19)  # string(JSON)

include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
cli_script_begin(cli_names.cmake RAYSPACE SRC WORK)

set(cornell "${SRC}/scenes/cornell-mirrors.json")
set(small --size 24x24 --no-oracle --out "${WORK}/x.png")

# Runs `rayspace render` on the Cornell scene, expecting exit 0; sets <var>_out and <var>_stats.
function(render var)
  math(EXPR n "${CASES} + 1")
  set(CASES ${n} PARENT_SCOPE)
  execute_process(COMMAND "${RAYSPACE}" render "${cornell}" ${small} --stats "${WORK}/${var}.json" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    set(FAILURES "${FAILURES}\n  [${var}] render ${ARGN}: exit ${rc}: ${err}" PARENT_SCOPE)
    set(${var}_stats "{}" PARENT_SCOPE)
    return()
  endif()
  file(READ "${WORK}/${var}.json" stats)
  set(${var}_out "${out}" PARENT_SCOPE)
  set(${var}_stats "${stats}" PARENT_SCOPE)
endfunction()

function(expect_match what text regex)
  if(NOT text MATCHES "${regex}")
    set(FAILURES "${FAILURES}\n  [${what}] does not match '${regex}':\n${text}" PARENT_SCOPE)
  endif()
endfunction()

# --- --levels, --depth and --bounces ------------------------------------------------------------
render(levels --levels 3)
render(depth --depth 3)
render(bounces0 --bounces 0)
render(plain)
expect_match("summary names the levels" "${levels_out}" "crsh \\(subdivision 8, 3 hierarchy levels, ")
expect_match("summary names the bounces" "${plain_out}" "bounces 2 from the scene's max_depth")
expect_match("--bounces in the summary" "${bounces0_out}" "bounces 0 from --bounces")
string(JSON levels_digest ERROR_VARIABLE jerr GET "${levels_stats}" digest)
string(JSON depth_digest ERROR_VARIABLE jerr GET "${depth_stats}" digest)
string(JSON levels_n ERROR_VARIABLE jerr GET "${levels_stats}" hierarchy_levels)
if(NOT levels_digest STREQUAL depth_digest OR NOT levels_n EQUAL 3)
  set(FAILURES "${FAILURES}\n  [--depth alias] --levels 3 digest ${levels_digest} (levels ${levels_n}), --depth 3 ${depth_digest}")
endif()
# --levels auto: the fewest levels (at least 2) that leave at most 512 top nodes for the pixels:
# 24x24 = 576 pixels need 2 at subdivision 8; 128x128 = 16,384 at subdivision 4 leave 1,024 top nodes
# with 2 levels and 256 with 3.
render(levels_auto_small --levels auto)
execute_process(COMMAND "${RAYSPACE}" render "${cornell}" --size 128x128 --no-oracle --out "${WORK}/x.png" --subdivision 4
                        --levels auto --stats "${WORK}/levels_auto.json" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
math(EXPR CASES "${CASES} + 1")
file(READ "${WORK}/levels_auto.json" levels_auto_stats)
string(JSON auto_small_n ERROR_VARIABLE jerr GET "${levels_auto_small_stats}" hierarchy_levels)
string(JSON auto_n ERROR_VARIABLE jerr GET "${levels_auto_stats}" hierarchy_levels)
if(NOT rc EQUAL 0 OR NOT auto_small_n EQUAL 2 OR NOT auto_n EQUAL 3)
  set(FAILURES "${FAILURES}\n  [--levels auto] 24x24: ${auto_small_n} levels (expected 2); 128x128, subdivision 4: ${auto_n} (expected 3), exit ${rc} ${err}")
endif()
string(JSON refl0 ERROR_VARIABLE jerr GET "${bounces0_stats}" rays reflection total)
string(JSON refl1 ERROR_VARIABLE jerr GET "${plain_stats}" rays reflection total)
string(JSON b0 ERROR_VARIABLE jerr GET "${bounces0_stats}" bounces)
if(NOT refl0 EQUAL 0 OR NOT refl1 GREATER 0 OR NOT b0 EQUAL 0)
  set(FAILURES "${FAILURES}\n  [--bounces 0] reflection rays ${refl0} (scene's max_depth: ${refl1}), bounces ${b0}")
endif()

# --- --help shows the defaults ------------------------------------------------------------------
execute_process(COMMAND "${RAYSPACE}" render --help RESULT_VARIABLE rc OUTPUT_VARIABLE help)
math(EXPR CASES "${CASES} + 1")
foreach(line "--algo TEXT:{[^}]*}=crsh" "--subdivision INT:{4,8,16}=8" "--levels,--depth TEXT:INT in \\[1 - 12\\] or auto=2"
             "--reduction TEXT:{hierarchical,scan}=hierarchical" "--depth is the same option" "--component-size [^\n]*=64"
             "--pair-capacity UINT:UINT in \\[subdivision\\^\\(levels-1\\) - 2\\^30\\]=16777216" "--bounces INT")
  expect_match("render --help" "${help}" "${line}")
endforeach()

# --- Flags the mode does not use ----------------------------------------------------------------
expect_warning(NAME "--subdivision with rah-quadtree" NEEDLES "rayspace render: warning: --subdivision 16 is ignored" "rah-quadtree"
               ARGS render "${cornell}" ${small} --algo rah-quadtree --subdivision 16)
expect_warning(NAME "--levels with brute" NEEDLES "--levels 3 is ignored" "--algo brute"
               ARGS render "${cornell}" ${small} --algo brute --levels 3)
expect_warning(NAME "hierarchy options with embree" WARNINGS 4 NEEDLES "--subdivision 4" "--reduction scan" "--pair-capacity 64" "--objects tree"
               ARGS render "${cornell}" ${small} --algo embree --subdivision 4 --reduction scan --pair-capacity 64 --objects tree)
expect_warning(NAME "--direct with crsh" NEEDLES "--direct bvh is ignored" "no direct tracer"
               ARGS render "${cornell}" ${small} --direct bvh)
expect_warning(NAME "--direct with embree --no-oracle" NEEDLES "--direct exhaustive is ignored"
               ARGS render "${cornell}" ${small} --algo embree --direct exhaustive)
expect_warning(NAME "--device with emu" NEEDLES "--device 0 is ignored" "--backend emu"
               ARGS render "${cornell}" ${small} --device 0)
expect_warning(NAME "--split-bytes with emu" NEEDLES "--split-bytes 65536 is ignored"
               ARGS render "${cornell}" ${small} --split-bytes 65536)
expect_warning(NAME "--tree-leaf with --objects flat" WARNINGS 2 NEEDLES "--tree-leaf 4" "--tree-big 0.5" "--objects flat"
               ARGS render "${cornell}" ${small} --objects flat --tree-leaf 4 --tree-big 0.5)
expect_warning(NAME "--reduction on the fused path" NEEDLES "--reduction scan is ignored" "--path passes"
               ARGS render "${cornell}" ${small} --reduction scan)
expect_warning(NAME "--component-size with --reduction scan" NEEDLES "--component-size 8 is ignored" "hierarchical"
               ARGS render "${cornell}" ${small} --path passes --reduction scan --component-size 8)
expect_warning(NAME "--path with brute" NEEDLES "--path passes is ignored"
               ARGS render "${cornell}" ${small} --algo brute --path passes)
expect_warning(NAME "bench --device without a Vulkan configuration" NEEDLES "rayspace bench: warning: --device 0 is ignored"
               ARGS bench "${cornell}" --sizes 16x16 --repetitions 1 --configs crsh --device 0)
# Flags the run does use draw none.
expect_warning(NAME "no warning: used flags" WARNINGS 0
               ARGS render "${cornell}" ${small} --subdivision 16 --levels 2 --path passes --reduction scan --objects tree --tree-leaf 4)
expect_warning(NAME "no warning: --direct with brute" WARNINGS 0 ARGS render "${cornell}" ${small} --algo brute --direct bvh)

# --- Refusals that name what would do -----------------------------------------------------------
expect_error(NAME "--pair-capacity below subdivision^(levels-1)" NEEDLES "--pair-capacity 4" "at least 8"
             ARGS render "${cornell}" ${small} --pair-capacity 4)
expect_error(NAME "--pair-capacity below 4^(levels-1) with rah-quadtree" NEEDLES "--pair-capacity 64" "at least 256"
             ARGS render "${cornell}" --size 32x32 --no-oracle --out "${WORK}/x.png" --algo rah-quadtree --pair-capacity 64)
render(capacity8 --pair-capacity 8 --objects flat)

if(VULKAN)
  expect_error(NAME "--device beyond the devices lists them" NEEDLES "--device 63" "0 '"
               ARGS render "${cornell}" ${small} --backend vulkan --device 63)
  expect_warning(NAME "diff: --subdivision with brute" NEEDLES "rayspace diff: warning: --subdivision 4 is ignored"
                 ARGS diff "${cornell}" --size 16x16 --algo brute --subdivision 4)
  # A planted fault: the first divergence names which backend computed which value.
  math(EXPR CASES "${CASES} + 1")
  execute_process(COMMAND "${RAYSPACE}" diff "${cornell}" --size 16x16 --inject raygen.shadow:1 --no-impact --report "${WORK}/report.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  expect_match("diff names the backends (exit ${rc})" "${err}" "first at [0-9]+ \\(word [0-9]+\\): emu [^,]+, vulkan ")
  file(READ "${WORK}/report.json" report)
  expect_match("diff report names the backends" "${report}" "\"expected_backend\": \"emu\"")
endif()

cli_script_end(cli.names)
