# `rayspace mutate` (docs/verification.md) in three parts, on cornell-mirrors at 32x32:
#   PART=sample (full tier)     12 mutants (one from each of 12 kernel files, in turn) and 2 spirv-opt variants chosen by this build's commit. Every
#                               mutant gets a verdict; a killed one names the pass that caught it (or why
#                               the frame failed); every variant diffs equal (a divergence is a compiler
#                               or driver finding to report, not to pass).
#   PART=targeted (default)     mutants the diff must kill (comparisons flipped in trim), one only a
#                               hand-made kernel case kills (the cone union's sign test), one only the
#                               clamping device kills (a private array read one past its end), every
#                               kernel case equal on the built-in kernels (--cases-only), and bad
#                               arguments refused with one line.
#   PART=configs (full tier)    mutants only the traversal lists' kernel cases and the added scenes'
#                               configurations kill.
#   PART=backends (full tier)   --backends emu,vulkan,sim: two mutants lavapipe runs benignly (a trim
#                               comparison that reads one word past its binding, a reduce constant that
#                               makes two subgroups write one word) survive there and die on the
#                               simulator, by memcheck and racecheck, listed in the report's differences.
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch> -DPART=sample|targeted|configs -P cli_mutate.cmake
cmake_minimum_required(VERSION 3.19)
if(NOT PART MATCHES "^(sample|targeted|configs|backends)$")
  message(FATAL_ERROR "cli_mutate.cmake: pass -DPART=sample, targeted, configs or backends")
endif()
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(FAILURES "")

if(PART STREQUAL "sample")

execute_process(COMMAND "${RAYSPACE}" mutate "${SRC}/scenes/cornell-mirrors.json" --limit 12 --variants 2 --seed commit --timeout 30
                        --jobs 2 --report "${WORK}/sample.json" --survivors "${SRC}/docs/mutation-survivors.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 2400)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cli.mutate: the sample: exit ${rc}\n${out}${err}")
endif()
message(STATUS "${out}")
file(READ "${WORK}/sample.json" j)
string(JSON seed GET "${j}" seed)
if(seed STREQUAL "commit" OR seed STREQUAL "")
  string(APPEND FAILURES "\nthe seed is not the commit: '${seed}'")
endif()
string(JSON n LENGTH "${j}" mutants)
if(NOT n EQUAL 12)
  string(APPEND FAILURES "\n${n} mutants, expected 12")
endif()
set(killed 0)
math(EXPR last "${n} - 1")
foreach(i RANGE ${last})
  string(JSON status GET "${j}" mutants ${i} status)
  string(JSON id GET "${j}" mutants ${i} id)
  if(NOT status MATCHES "^(killed|survived|equivalent|stillborn|invalid)$")
    string(APPEND FAILURES "\n${id}: status '${status}'")
  endif()
  if(status STREQUAL "killed")
    math(EXPR killed "${killed} + 1")
    string(JSON pass ERROR_VARIABLE no_pass GET "${j}" mutants ${i} caught pass)
    string(JSON reason ERROR_VARIABLE no_reason GET "${j}" mutants ${i} reason)
    if((no_pass OR pass STREQUAL "" OR pass STREQUAL "null") AND (no_reason OR reason STREQUAL ""))
      string(APPEND FAILURES "\n${id}: killed without a pass or a reason")
    endif()
  endif()
endforeach()
if(killed EQUAL 0)
  string(APPEND FAILURES "\nno mutant of 12 killed")
endif()
string(JSON nv LENGTH "${j}" variants)
if(NOT nv EQUAL 2)
  string(APPEND FAILURES "\n${nv} variants, expected 2")
else()
  foreach(i 0 1)
    string(JSON vs GET "${j}" variants ${i} status)
    string(JSON vk GET "${j}" variants ${i} kernel)
    string(JSON vr GET "${j}" variants ${i} recipe)
    if(NOT vs STREQUAL "equal")
      string(APPEND FAILURES "\nvariant ${vk} through spirv-opt ${vr}: ${vs} (a compiler or driver finding: see docs/verification.md)")
    endif()
  endforeach()
endif()
if(FAILURES)
  message(FATAL_ERROR "cli.mutate.sample:${FAILURES}")
endif()
message(STATUS "cli.mutate.sample: ${killed} of 12 sampled mutants killed, both variants equal")
return()
endif()

# One targeted run (every mutant of --only in one configuration, no variants) into WORK/NAME.json:
# sets `json` (empty when the command failed, which is recorded) and `log` in the caller.
function(mutate_one name config only)
  execute_process(COMMAND "${RAYSPACE}" mutate "${SRC}/scenes/cornell-mirrors.json" --config ${config} --only "${only}"
                          --limit 0 --variants 0 --timeout 30 --report "${WORK}/${name}.json" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 1200)
  set(json "" PARENT_SCOPE)
  set(log "${out}" PARENT_SCOPE)
  if(NOT rc EQUAL 0)
    set(FAILURES "${FAILURES}\n${name}: exit ${rc}\n${out}${err}" PARENT_SCOPE)
  else()
    file(READ "${WORK}/${name}.json" j)
    set(json "${j}" PARENT_SCOPE)
  endif()
endfunction()

# The verdicts of a mutate_one report, sorted: `seen` holds ID=STATUS:CASE:DEVICE per mutant (CASE and
# DEVICE empty unless a kernel case or the clamping device killed it).
function(verdicts json)
  set(out "")
  if(json)
    string(JSON n LENGTH "${json}" mutants)
    if(n GREATER 0)
      math(EXPR last "${n} - 1")
      foreach(i RANGE ${last})
        string(JSON id GET "${json}" mutants ${i} id)
        string(JSON status GET "${json}" mutants ${i} status)
        string(JSON by ERROR_VARIABLE no_case GET "${json}" mutants ${i} caught case)
        string(JSON device ERROR_VARIABLE no_device GET "${json}" mutants ${i} caught device)
        if(no_case)
          set(by "")
        endif()
        if(no_device)
          set(device "")
        endif()
        list(APPEND out "${id}=${status}:${by}:${device}")
      endforeach()
    endif()
  endif()
  list(SORT out)
  set(seen "${out}" PARENT_SCOPE)
endfunction()

if(PART STREQUAL "targeted")
# Mutants the diff must kill: trim keeps the flagged slots; flipping its tests loses or invents rays.
# Four named ones (a survivor costs a run of every kernel case and the clamping device; the sample in
# the full tier meets the others). And, in the same run (one baseline for both), a mutant only a
# kernel case kills: the cone union's sign test moved one ulp (0.0 -> the smallest subnormal, written
# as its bits) changes the answer only where the union's sine is exactly 0, which no frame's build
# meets and the case build-parents-boundaries holds. The built-in kernels must replay equal first
# (the command fails otherwise) the cases of the passes these mutants change, build's three and
# intersect's (cone.glsl is in both kernels), and only those: the other eight are listed as skipped.
mutate_one(crsh crsh "^(trim.comp:(26:16|32:11|51:63|53:15):comparison:|cone.glsl:118:12:float-ulp:)")
verdicts("${json}")
if(json)
  string(JSON by GET "${json}" summary per_file trim.comp passes 0)
  string(JSON ncases LENGTH "${json}" kernel_cases)
  set(replayed "")
  math(EXPR last "${ncases} - 1")
  foreach(i RANGE ${last})
    string(JSON name GET "${json}" kernel_cases ${i} name)
    string(JSON skipped ERROR_VARIABLE ran GET "${json}" kernel_cases ${i} skipped)
    if(ran)
      list(APPEND replayed "${name}")
    endif()
  endforeach()
  list(LENGTH seen n)
  list(FILTER seen INCLUDE REGEX "^trim\\.comp:.*=killed::$|^cone\\.glsl:118:12:float-ulp:.*=killed:build-parents-boundaries:$")
  list(LENGTH seen k)
  set(want_replayed "build-parents-boundaries;build-parents-boundaries-pairwise;build-leaves-boundaries;intersect-axis-rays")
  if(NOT n EQUAL 5 OR NOT k EQUAL 5 OR NOT by STREQUAL "trim" OR ncases LESS 12 OR NOT replayed STREQUAL want_replayed)
    string(APPEND FAILURES "\ntrim's comparisons killed by the diff in trim, cone.glsl:118's sign test by the case "
           "build-parents-boundaries: ${k} of ${n} (5 expected), trim.comp's passes '${by}', ${ncases} kernel cases listed, "
           "replayed '${replayed}' (want '${want_replayed}')\n${log}")
  endif()
endif()
# --cases-only replays every case with the built-in kernels and nothing else; each is named equal.
execute_process(COMMAND "${RAYSPACE}" mutate --cases-only --report "${WORK}/cases.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 600)
string(REGEX MATCHALL "\n  [a-z-]+ \\([a-z.]+\\): equal" equal_lines "${out}")
list(LENGTH equal_lines nequal)
set(ncases 0)
if(EXISTS "${WORK}/cases.json")
  file(READ "${WORK}/cases.json" cases_json)
  string(JSON ncases ERROR_VARIABLE jerr LENGTH "${cases_json}" kernel_cases)
endif()
if(NOT rc EQUAL 0 OR nequal LESS 12 OR NOT nequal EQUAL ncases OR NOT out MATCHES "every kernel case equal")
  string(APPEND FAILURES "\n--cases-only: exit ${rc}, ${nequal} cases named equal, ${ncases} in the report (12 or more, all equal "
         "expected)\n${out}${err}")
endif()

endif()

if(PART STREQUAL "configs")
# Two more that only kernel cases kill, in the traversal lists' configuration: Woop's axis choice left
# at x when y is largest divides by a zero component for a ray along y (intersect-axis-rays; the
# watertight test is shared with tl.trace), and ties of direction components sent to the z list
# change where an any-hit walk stops (tl-trace-ties).
mutate_one(cases tl "^(watertight.glsl:10:25:constant:0|tl.glsl:39:13:comparison:>=)$")
verdicts("${json}")
set(want "tl.glsl:39:13:comparison:>==killed:tl-trace-ties:;watertight.glsl:10:25:constant:0=killed:intersect-axis-rays:")
if(json AND NOT seen STREQUAL want)
  string(APPEND FAILURES "\nkernel cases intersect-axis-rays and tl-trace-ties: got '${seen}', want '${want}'\n${log}")
endif()

# Mutants only the added scenes kill: on the procedural roger-wavy-n32, the node counts of a one-child
# object node's pair put under its one triangle candidate's counters (tree-one-child), and the grid
# build's block sums over a block range that is right only while every triangle fits one scan block
# (grid-blocks); with the light in the ceiling's plane, front-face culling's side test moved off 0
# (grid-coplanar).
mutate_one(scenes "tree-one-child;--config;grid-blocks;--config;grid-coplanar"
           "^(tree_test.comp:30:54:constant:1u|grid_build.comp:397:60:arithmetic:-|grid.glsl:14:.*)$")
verdicts("${json}")
set(want "grid.glsl:14:21:comparison:<==killed::" "grid.glsl:14:23:float-ulp:uintBitsToFloat(0x00000001u)=killed::"
         "grid_build.comp:397:60:arithmetic:-=killed::" "tree_test.comp:30:54:constant:1u=killed::")
if(json AND NOT seen STREQUAL want)
  string(APPEND FAILURES "\nthe added scenes' configurations: got '${seen}', want '${want}'\n${log}")
endif()

endif()

if(PART STREQUAL "targeted")
# A mutant only the clamping device kills: a loop one past the window's four corners reads and writes
# private arrays out of bounds, which lavapipe lets pass unseen; clamped, the fifth side plane
# overwrites the fourth. One only the case tl-heads-slivers kills: the sliver test reading a zero
# edge, so that slivers get windows from planes their float normal cannot give. And one only
# tl-heads-touching kills: a facet's rejection moved onto its bound less the margin, at its first
# vertex (89:65 and 89:76 are the same mistake at the other two, and cost a case run each).
mutate_one(clamped tl-heads "^(tl_cells.comp:32:23:comparison:<=|tl_heads.comp:60:58:component:y|tl_heads.comp:89:54:comparison:<=)$")
verdicts("${json}")
set(want "tl_cells.comp:32:23:comparison:<==killed::clamped;tl_heads.comp:60:58:component:y=killed:tl-heads-slivers:"
         "tl_heads.comp:89:54:comparison:<==killed:tl-heads-touching:")
if(json)
  string(JSON base ERROR_VARIABLE no_base GET "${json}" clamped_baseline tl-heads)
  if(NOT seen STREQUAL want OR NOT base STREQUAL "equal")
    string(APPEND FAILURES "\nclamped device, tl-heads-slivers and tl-heads-touching: got '${seen}', want '${want}', clamped baseline '${base}'\n${log}")
  endif()
endif()

# Bad arguments: one line naming the option, exit 2.
foreach(bad "--pass;nosuch" "--variants;x" "--pass;raster" "--config;nosuch" "--survivors;${WORK}/none.json" "--cases-only;--list"
        "--cases-only;--size;8x8")
  execute_process(COMMAND "${RAYSPACE}" mutate "${SRC}/scenes/cornell-mirrors.json" ${bad} --limit 1 RESULT_VARIABLE rc OUTPUT_QUIET
                  ERROR_VARIABLE err TIMEOUT 300)
  list(GET bad 0 flag)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "${flag}")
    string(APPEND FAILURES "\n${bad}: exit ${rc}, ${err}")
  endif()
endforeach()
execute_process(COMMAND "${RAYSPACE}" mutate "${WORK}/missing.json" --limit 1 RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err TIMEOUT 300)
if(NOT rc EQUAL 2 OR NOT err MATCHES "missing.json")
  string(APPEND FAILURES "\na missing scene: exit ${rc}, ${err}")
endif()
# Every argument is checked before any work: each refusal comes at once (well under the baseline's
# seconds), with exit 2 naming the flag.
file(WRITE "${WORK}/garbage.json" "[1, 2")
file(WRITE "${WORK}/afile" "")
foreach(bad "--only;(" "--limit;-1" "--survivors;${WORK}/garbage.json" "--work;${WORK}/afile")
  string(TIMESTAMP t0 "%s")
  execute_process(COMMAND "${RAYSPACE}" mutate "${SRC}/scenes/cornell-mirrors.json" ${bad} RESULT_VARIABLE rc OUTPUT_QUIET
                  ERROR_VARIABLE err TIMEOUT 300)
  string(TIMESTAMP t1 "%s")
  math(EXPR took "${t1} - ${t0}")
  list(GET bad 0 flag)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "${flag}" OR took GREATER 5)
    string(APPEND FAILURES "\n${bad}: exit ${rc} after ${took} s, expected 2 at once naming ${flag}: ${err}")
  endif()
endforeach()
# Its scratch directory under $TMPDIR goes on every exit: 0 (--list), 2, and SIGTERM mid-run.
set(tmp "${WORK}/tmpdir")
file(REMOVE_RECURSE "${tmp}")
file(MAKE_DIRECTORY "${tmp}")
execute_process(COMMAND ${CMAKE_COMMAND} -E env TMPDIR=${tmp} "${RAYSPACE}" mutate "${SRC}/scenes/cornell-mirrors.json" --list --limit 2
                        --config crsh RESULT_VARIABLE rc_list OUTPUT_QUIET ERROR_VARIABLE err TIMEOUT 300)
execute_process(COMMAND ${CMAKE_COMMAND} -E env TMPDIR=${tmp} "${RAYSPACE}" mutate "${SRC}/scenes/cornell-mirrors.json" --config nosuch
                RESULT_VARIABLE rc_bad OUTPUT_QUIET ERROR_QUIET TIMEOUT 300)
execute_process(COMMAND ${CMAKE_COMMAND} -E env TMPDIR=${tmp} timeout -s TERM 4 "${RAYSPACE}" mutate
                        "${SRC}/scenes/cornell-mirrors.json" --limit 5 --config crsh
                RESULT_VARIABLE rc_term OUTPUT_QUIET ERROR_QUIET TIMEOUT 300)
# The diffs it ran, ended by the same signal, finish dying; its cleaner removes what they leave.
# Removed within seconds, not at once: the directory is polled for up to 10 s.
foreach(i RANGE 50)
  file(GLOB left "${tmp}/*")
  if(NOT left)
    break()
  endif()
  execute_process(COMMAND sleep 0.2)
endforeach()
if(left)
  file(GLOB_RECURSE left_tree LIST_DIRECTORIES true "${tmp}/*")  # what was left, to say who wrote it
  set(left "${left}: ${left_tree}")
endif()
if(NOT rc_list EQUAL 0 OR NOT rc_bad EQUAL 2 OR NOT rc_term EQUAL 124 OR left)
  string(APPEND FAILURES "\nscratch directory: --list exit ${rc_list}, a bad --config exit ${rc_bad}, SIGTERM after 4 s exit ${rc_term} (124: "
                         "timeout's), left under TMPDIR: ${left}; ${err}")
endif()

endif()

if(PART STREQUAL "backends")
  execute_process(COMMAND "${RAYSPACE}" mutate "${SRC}/scenes/cornell-mirrors.json" --limit 0 --config crsh --size 16x16 --variants 0
                          --only "trim.comp:46:24:comparison:<=|reduce.comp:89:29:constant:2u" --backends emu,vulkan,sim
                          --report "${WORK}/backends.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT EXISTS "${WORK}/backends.json")
    string(APPEND FAILURES "\nmutate --backends emu,vulkan,sim: exit ${rc}: ${out}${err}")
  else()
    file(READ "${WORK}/backends.json" j)
    string(JSON n ERROR_VARIABLE jerr LENGTH "${j}" on_sim differences)
    set(seen "")
    if(NOT jerr)
      math(EXPR last "${n} - 1")
      foreach(i RANGE ${last})
        string(JSON id GET "${j}" on_sim differences ${i} id)
        string(JSON on_vulkan GET "${j}" on_sim differences ${i} vulkan)
        string(JSON on_sim GET "${j}" on_sim differences ${i} sim)
        string(JSON checker ERROR_VARIABLE cerr GET "${j}" on_sim differences ${i} caught checker)
        list(APPEND seen "${id}:${on_vulkan}:${on_sim}:${checker}")
      endforeach()
    endif()
    foreach(want "trim.comp:46:24:comparison:<=:survived:killed:memcheck" "reduce.comp:89:29:constant:2u:survived:killed:racecheck")
      if(NOT want IN_LIST seen)
        string(APPEND FAILURES "\nmutate --backends emu,vulkan,sim: expected ${want} among the differences, got '${seen}'")
      endif()
    endforeach()
    if(NOT out MATCHES "2 mutant\\(s\\) with another verdict on sim than on vulkan")
      string(APPEND FAILURES "\nmutate --backends emu,vulkan,sim: no list of differences printed: ${out}")
    endif()
  endif()
endif()

if(FAILURES)
  message(FATAL_ERROR "cli.mutate.${PART}:${FAILURES}")
endif()
if(PART STREQUAL "backends")
  message(STATUS "cli.mutate.backends: two mutants survive lavapipe and die on the simulator")
elseif(PART STREQUAL "targeted")
  message(STATUS "cli.mutate.targeted: trim's comparisons killed, the cone union's sign test killed by a kernel case, a private-array overrun by the clamping device")
else()
  message(STATUS "cli.mutate.configs: the traversal lists' kernel cases and the added scenes' configurations kill their mutants")
endif()
