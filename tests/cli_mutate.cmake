# `rayspace mutate` (docs/verification.md) as CI runs it: about 20 mutants and 2 spirv-opt variants,
# chosen by this build's commit, on cornell-mirrors at 32x32. Every mutant gets a verdict; a killed
# one names the pass that caught it (or why the frame failed); every variant diffs equal (a
# divergence is a compiler or driver finding to report, not to pass). Then a mutant the diff must
# kill (a comparison flipped in trim's scatter), one only a hand-made kernel case kills (the cone
# union's sign test), one only the clamping device kills (a private array read one past its end),
# and bad arguments refused with one line.
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch> -P cli_mutate.cmake
cmake_minimum_required(VERSION 3.19)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(FAILURES "")

execute_process(COMMAND "${RAYSPACE}" mutate "${SRC}/scenes/cornell-mirrors.json" --limit 20 --variants 2 --seed commit --timeout 30
                        --jobs 2 --report "${WORK}/sample.json" --survivors "${SRC}/docs/mutation-survivors.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 1200)
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
if(NOT n EQUAL 20)
  string(APPEND FAILURES "\n${n} mutants, expected 20")
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
  string(APPEND FAILURES "\nno mutant of 20 killed")
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

# A mutant the diff must kill: trim's scatter keeps the flagged slots; flipping that test loses rays.
execute_process(COMMAND "${RAYSPACE}" mutate "${SRC}/scenes/cornell-mirrors.json" --pass trim --config crsh --only ":comparison:"
                        --limit 0 --variants 0 --timeout 30 --report "${WORK}/trim.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 1200)
if(NOT rc EQUAL 0)
  string(APPEND FAILURES "\ntrim's comparisons: exit ${rc}\n${out}${err}")
else()
  file(READ "${WORK}/trim.json" j)
  string(JSON k GET "${j}" summary killed)
  string(JSON by GET "${j}" summary per_file trim.comp passes 0)
  if(k LESS 3 OR NOT by STREQUAL "trim")
    string(APPEND FAILURES "\ntrim's comparisons: ${k} killed (expected at least 3), passes '${by}'\n${out}")
  endif()
endif()

# A mutant only a kernel case kills: the cone union's sign test moved one ulp (0.0 -> the smallest
# subnormal, written as its bits) changes the answer only where the union's sine is exactly 0, which
# no frame's build meets and the case build-parents-boundaries holds. The built-in kernels must
# replay every case equal first (the command fails otherwise).
execute_process(COMMAND "${RAYSPACE}" mutate "${SRC}/scenes/cornell-mirrors.json" --config crsh --only "^cone.glsl:118:12:float-ulp:"
                        --limit 0 --variants 0 --timeout 30 --report "${WORK}/case.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 1200)
if(NOT rc EQUAL 0)
  string(APPEND FAILURES "\nthe kernel case: exit ${rc}\n${out}${err}")
else()
  file(READ "${WORK}/case.json" j)
  string(JSON status GET "${j}" mutants 0 status)
  string(JSON by ERROR_VARIABLE no_case GET "${j}" mutants 0 caught case)
  string(JSON ncases LENGTH "${j}" kernel_cases)
  if(NOT status STREQUAL "killed" OR NOT by STREQUAL "build-parents-boundaries" OR ncases LESS 4)
    string(APPEND FAILURES "\ncone.glsl:118's sign test: ${status}, caught by case '${by}', ${ncases} kernel cases\n${out}")
  endif()
endif()

# A mutant only the clamping device kills: a loop one past the window's four corners reads and writes
# private arrays out of bounds, which lavapipe lets pass unseen; clamped, the fifth side plane
# overwrites the fourth.
execute_process(COMMAND "${RAYSPACE}" mutate "${SRC}/scenes/cornell-mirrors.json" --config tl-heads --only "^tl_cells.comp:32:23:comparison:<=$"
                        --limit 0 --variants 0 --timeout 30 --report "${WORK}/clamped.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 1200)
if(NOT rc EQUAL 0)
  string(APPEND FAILURES "\nthe clamping device: exit ${rc}\n${out}${err}")
else()
  file(READ "${WORK}/clamped.json" j)
  string(JSON status GET "${j}" mutants 0 status)
  string(JSON device ERROR_VARIABLE no_device GET "${j}" mutants 0 caught device)
  string(JSON base ERROR_VARIABLE no_base GET "${j}" clamped_baseline tl-heads)
  if(NOT status STREQUAL "killed" OR NOT device STREQUAL "clamped" OR NOT base STREQUAL "equal")
    string(APPEND FAILURES "\ntl_cells.comp:32's corner loop: ${status}, device '${device}', clamped baseline '${base}'\n${out}")
  endif()
endif()

# Bad arguments: one line naming the option, exit 2.
foreach(bad "--pass;nosuch" "--variants;x" "--pass;raster" "--config;nosuch" "--survivors;${WORK}/none.json")
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

if(FAILURES)
  message(FATAL_ERROR "cli.mutate:${FAILURES}")
endif()
message(STATUS "cli.mutate: ${killed} of 20 sampled mutants killed, both variants equal, trim's comparisons killed, the cone union's sign test killed by a kernel case, a private-array overrun by the clamping device")
