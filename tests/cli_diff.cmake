# `rayspace diff`: the Vulkan kernels equal the emulator on the bundled scenes, and every planted
# fault makes the diff fail with its own pass reported first.
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DDATA=<data root> -DWORK=<scratch> -P cli_diff.cmake
set(failures "")
file(MAKE_DIRECTORY "${WORK}")

function(diff_run name scene size inject expect_rc expect_first)
  set(extra ${ARGN})
  if(inject)
    list(APPEND extra --inject ${inject})
  endif()
  set(path "${SRC}/scenes/${scene}.json")
  if(scene MATCHES "\\.json$")
    set(path "${scene}")
  endif()
  execute_process(COMMAND "${RAYSPACE}" diff "${path}" --data "${DATA}" --size ${size}
                          --report "${WORK}/${name}.json" ${extra}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL expect_rc)
    set(failures "${failures}\n${name}: exit ${rc}, expected ${expect_rc}: ${out}${err}" PARENT_SCOPE)
    return()
  endif()
  file(READ "${WORK}/${name}.json" j)
  string(JSON first GET "${j}" first_divergent_pass)  # JSON null reads as ""
  string(JSON equal GET "${j}" equal)
  if(expect_rc EQUAL 0 AND NOT equal)
    set(failures "${failures}\n${name}: report says not equal" PARENT_SCOPE)
  endif()
  if(NOT "${first}" STREQUAL "${expect_first}")
    set(failures "${failures}\n${name}: first divergent pass '${first}', expected '${expect_first}'" PARENT_SCOPE)
  endif()
endfunction()

diff_run(cornell cornell-mirrors 512x512 "" 0 "")
diff_run(office office 128x128 "" 0 "")
# A transparent object brings the refraction kernels in.
file(READ "${SRC}/scenes/cornell-mirrors.json" cornell)
string(JSON glass SET "${cornell}" materials clay transparency 0.5)
string(JSON glass SET "${glass}" materials clay reflectivity 0.2)
string(JSON glass SET "${glass}" materials clay ior 1.5)
file(WRITE "${WORK}/glass-scene.json" "${glass}")
diff_run(glass "${WORK}/glass-scene.json" 128x128 "" 0 "")
diff_run(inject_refraction "${WORK}/glass-scene.json" 96x96 raygen.refraction:1 4 raygen.refraction)
# Workgroup sizes must not change a bit (order-preserving compaction, order-independent reductions).
foreach(ls 1 7 256)
  diff_run(cornell_ls${ls} cornell-mirrors 96x96 "" 0 "" --local-size ${ls})
endforeach()
if(EXISTS "${DATA}/sponza_dabrovic/sponza.obj")
  diff_run(sponza sponza 128x128 "" 0 "")
endif()
foreach(f raster:1 surfaces:1 raygen.shadow:1 raygen.shadow:2 trim.shadow:1 hash.shadow:1 compress.shadow:1 sort.shadow:1
                decompress.shadow:1 build.shadow:1 traverse.shadow:1 reduce.shadow:1 intersect.shadow:1 shade:1 raygen.reflection:1 trim.reflection:1 resolve:1)
  string(REPLACE ":" "_" n "${f}")
  string(REGEX REPLACE ":.*" "" pass "${f}")
  diff_run(inject_${n} cornell-mirrors 64x64 ${f} 4 ${pass})
endforeach()

# A device index that does not exist is bad input: exit 2 and one line naming the option.
execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --device 63
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--device 63")
  set(failures "${failures}\n--device 63: exit ${rc}, stderr '${err}'")
endif()

if(failures)
  message(FATAL_ERROR "${failures}")
endif()
message(STATUS "diff: kernels equal the emulator; every planted fault is caught at its pass")
