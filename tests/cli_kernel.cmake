# `--kernel PASS=FILE`: a user's kernel runs in place of the built-in one (docs/kernels.md).
# A copy of the built-in reduce kernel gives all passes equal; a planted bug in the copy makes the diff
# fail (exit 4) with `reduce` first; a binding outside the contract is refused before anything runs
# (exit 2, naming the binding); so are an unknown pass, a missing file and GLSL that does not compile,
# and, after the run, a kernel whose pass the run never launched.
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch> -P cli_kernel.cmake
cmake_minimum_required(VERSION 3.19)
file(MAKE_DIRECTORY "${WORK}")
set(failures "")
set(scene "${SRC}/scenes/cornell-mirrors.json")

# run(name expect_rc expect_text args...): expect_text must appear in stdout+stderr.
function(run name expect_rc expect_text)
  execute_process(COMMAND "${RAYSPACE}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL expect_rc)
    set(failures "${failures}\n${name}: exit ${rc}, expected ${expect_rc}: ${out}${err}" PARENT_SCOPE)
    return()
  endif()
  string(FIND "${out}${err}" "${expect_text}" at)
  if(at EQUAL -1)
    set(failures "${failures}\n${name}: output lacks '${expect_text}': ${out}${err}" PARENT_SCOPE)
  endif()
endfunction()

function(first_pass name expect)
  file(READ "${WORK}/${name}.json" j)
  string(JSON first GET "${j}" first_divergent_pass)
  if(NOT "${first}" STREQUAL "${expect}")
    set(failures "${failures}\n${name}: first divergent pass '${first}', expected '${expect}'" PARENT_SCOPE)
  endif()
endfunction()

file(READ "${SRC}/gpu/shaders/reduce.comp" reduce)
file(WRITE "${WORK}/my_reduce.comp" "${reduce}")
run(copy 0 "all passes equal" diff "${scene}" --size 96x96 --kernel reduce=${WORK}/my_reduce.comp --report "${WORK}/copy.json")
first_pass(copy "")
# The scan-based reduction runs other phases of the same kernel.
run(copy_scan 0 "all passes equal" diff "${scene}" --size 64x64 --reduction scan --kernel reduce=${WORK}/my_reduce.comp)

# A planted bug: the concatenation drops the last element of every segment.
string(REPLACE "k < len; k += lanes)" "k + 1u < len; k += lanes)" buggy "${reduce}")
if(buggy STREQUAL reduce)
  set(failures "${failures}\nplanted bug: reduce.comp no longer has the concatenation loop this test edits")
endif()
file(WRITE "${WORK}/buggy_reduce.comp" "${buggy}")
run(buggy 4 "reduce" diff "${scene}" --size 96x96 --kernel reduce=${WORK}/buggy_reduce.comp --report "${WORK}/buggy.json")
first_pass(buggy reduce)
# The same bug in a render (the passes path runs reduce): its lost pairs leave words the kernel never
# wrote, and the check of the device's outputs where the backend returns them stops the frame (exit 1)
# as a device output error naming the call, its level, the backend, the buffer and the element,
# before anything reads with them; nothing is left behind.
file(REMOVE "${WORK}/buggy.png")
execute_process(COMMAND "${RAYSPACE}" render "${scene}" --size 64x64 --backend vulkan --path passes --out "${WORK}/buggy.png"
                        --kernel reduce=${WORK}/buggy_reduce.comp
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR NOT err MATCHES "rayspace: device output error: reduce \\(reduce\\.L[0-9]+\\.[a-z]+\\.b[0-9]+\\) from the vulkan backend: output 'pairs' element [0-9]+ "
   OR EXISTS "${WORK}/buggy.png")
  set(failures "${failures}\nrender_buggy: exit ${rc} (expected 1), stderr '${err}'")
endif()

# A binding outside the contract.
string(REPLACE "binding = kReduceBindOut)" "binding = 9)" wrong "${reduce}")
file(WRITE "${WORK}/wrong_binding.comp" "${wrong}")
run(wrong_binding 2 "binding 9" diff "${scene}" --size 32x32 --kernel reduce=${WORK}/wrong_binding.comp)

# SPIR-V is taken as it is: the built-in kernel compiled by hand, if glslc is on the PATH.
find_program(GLSLC glslc)
if(GLSLC)
  execute_process(COMMAND ${GLSLC} -O0 --target-env=vulkan1.2 -I ${SRC}/gpu/shaders -I ${SRC}/core/contract/include
                          ${WORK}/my_reduce.comp -o ${WORK}/my_reduce.spv RESULT_VARIABLE rc)
  run(spv 0 "all passes equal" diff "${scene}" --size 64x64 --kernel reduce=${WORK}/my_reduce.spv)
endif()

# Bad input: one line naming it, exit 2.
run(unknown_pass 2 "no pass named 'reducer'" diff "${scene}" --size 32x32 --kernel reducer=${WORK}/my_reduce.comp)
run(no_equals 2 "expected PASS=FILE" diff "${scene}" --size 32x32 --kernel reduce)
run(missing_file 2 "not found" diff "${scene}" --size 32x32 --kernel reduce=${WORK}/none.comp)
file(WRITE "${WORK}/broken.comp" "#version 460\nvoid main() { undefined_thing(); }\n")
run(broken 2 "does not compile" diff "${scene}" --size 32x32 --kernel reduce=${WORK}/broken.comp)
run(raster 2 "graphics pipeline" diff "${scene}" --size 32x32 --kernel raster=${WORK}/my_reduce.comp)
run(emu_backend 2 "--backend vulkan" render "${scene}" --size 32x32 --no-oracle --out ${WORK}/x.png --kernel reduce=${WORK}/my_reduce.comp)
# render with the copy gives the emulator's digest.
run(render_emu 0 "digest" render "${scene}" --size 64x64 --no-oracle --out ${WORK}/emu.png --stats ${WORK}/emu.json)
run(render_copy 0 "digest" render "${scene}" --size 64x64 --no-oracle --backend vulkan --path passes --out ${WORK}/copy.png
    --stats ${WORK}/copy_render.json --kernel reduce=${WORK}/my_reduce.comp)
if(EXISTS "${WORK}/emu.json" AND EXISTS "${WORK}/copy_render.json")
  file(READ "${WORK}/emu.json" je)
  file(READ "${WORK}/copy_render.json" jc)
  string(JSON de GET "${je}" digest)
  string(JSON dc GET "${jc}" digest)
  if(NOT de STREQUAL dc)
    set(failures "${failures}\nrender_copy: digest ${dc}, the emulator's is ${de}")
  endif()
else()
  set(failures "${failures}\nrender_copy: no statistics written")
endif()

# A kernel the run never launches is refused after the run, naming the pass and the options that run
# it (exit 2), with no verdict and no output: render's fused default and diff --path fused have no
# reduce pass; a replayed reduce call runs no trim kernel.
file(READ "${SRC}/gpu/shaders/trim.comp" trim)
file(WRITE "${WORK}/my_trim.comp" "${trim}")
file(REMOVE "${WORK}/unreached.png" "${WORK}/unreached.json")
run(render_unreached 2 "this run never launched pass 'reduce' (it runs with --path passes and --algo crsh" render "${scene}" --size 32x32
    --no-oracle --backend vulkan --out ${WORK}/unreached.png --stats ${WORK}/unreached.json --kernel reduce=${WORK}/my_reduce.comp)
if(EXISTS "${WORK}/unreached.png" OR EXISTS "${WORK}/unreached.json")
  set(failures "${failures}
render_unreached: an output was written for a run refused")
endif()
execute_process(COMMAND "${RAYSPACE}" diff "${scene}" --size 32x32 --path fused --kernel reduce=${WORK}/my_reduce.comp
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR out MATCHES "equal" OR NOT err MATCHES "never launched pass 'reduce'.*the run launched: [a-z]")
  set(failures "${failures}
diff_unreached: exit ${rc}, expected 2 with no verdict: ${out}${err}")
endif()
# A frame stopped by a divergence before a given kernel's pass has its verdict (exit 4), not "never
# launched": the sort kernel diverges (planted) and decompress, which the same file serves, cannot run.
file(READ "${SRC}/gpu/shaders/sort.comp" sort)
file(WRITE "${WORK}/my_sort.comp" "${sort}")
run(stopped_before 4 "first divergent pass: sort" diff "${scene}" --size 16x16 --path passes --inject sort:1 --no-impact
    --kernel decompress=${WORK}/my_sort.comp)
file(REMOVE_RECURSE "${WORK}/saved")
execute_process(COMMAND "${RAYSPACE}" diff "${scene}" --size 16x16 --path passes --save-inputs "${WORK}/saved"
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
file(GLOB reduce_call "${WORK}/saved/*-reduce*")
if(NOT rc EQUAL 0 OR NOT reduce_call)
  set(failures "${failures}
replay_unreached: the diff saving calls failed (exit ${rc}) or saved no reduce call: ${err}")
else()
  list(GET reduce_call 0 reduce_call)
  run(replay_reached 0 "equal" replay "${reduce_call}" --kernel reduce=${WORK}/my_reduce.comp)
  run(replay_unreached 2 "this run never launched pass 'trim'" replay "${reduce_call}" --kernel trim=${WORK}/my_trim.comp)
endif()

if(failures)
  message(FATAL_ERROR "cli.kernel failures:${failures}")
endif()
message(STATUS "cli.kernel: all checks passed")
