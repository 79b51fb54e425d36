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
diff_run(cornell_rah cornell-mirrors 128x128 "" 0 "" --algo rah)
diff_run(cornell_quadtree cornell-mirrors 96x96 "" 0 "" --algo rah-quadtree)
diff_run(cornell_scan cornell-mirrors 128x128 "" 0 "" --reduction scan)
diff_run(cornell_brute cornell-mirrors 96x96 "" 0 "" --algo brute)
diff_run(office office 128x128 "" 0 "")
diff_run(office_rah office 96x96 "" 0 "" --algo rah)
# A transparent object brings the refraction kernels in.
file(READ "${SRC}/scenes/cornell-mirrors.json" cornell)
string(JSON glass SET "${cornell}" materials clay transparency 0.5)
string(JSON glass SET "${glass}" materials clay reflectivity 0.2)
string(JSON glass SET "${glass}" materials clay ior 1.5)
file(WRITE "${WORK}/glass-scene.json" "${glass}")
diff_run(glass "${WORK}/glass-scene.json" 128x128 "" 0 "")
diff_run(inject_refraction "${WORK}/glass-scene.json" 96x96 raygen.refraction:1 4 raygen.refraction)
# Workgroup sizes and dispatch splitting must not change a bit (order-preserving compaction,
# order-independent reductions).
foreach(ls 1 7 256)
  diff_run(cornell_ls${ls} cornell-mirrors 96x96 "" 0 "" --local-size ${ls})
endforeach()
# Bindings far below maxStorageBufferRange: parts, pages, pair-stream splits; launches in rows.
diff_run(cornell_paged cornell-mirrors 96x96 "" 0 "" --split-bytes 163840)
diff_run(cornell_paged_scan cornell-mirrors 96x96 "" 0 "" --split-bytes 163840 --reduction scan)
diff_run(cornell_split cornell-mirrors 48x40 "" 0 "" --split-bytes 65536)
diff_run(cornell_rows cornell-mirrors 96x96 "" 0 "" --max-groups 2)
file(READ "${WORK}/cornell_paged.json" j)
string(JSON splits GET "${j}" split_dispatches)
string(JSON paged GET "${j}" paged_arrays)
if(splits LESS 100 OR paged LESS 10)
  set(failures "${failures}\ncornell_paged: ${splits} split dispatches, ${paged} paged arrays; the paths did not run")
endif()
# Faults that only the split, paged or folded paths can show; each fails its own pass first.
diff_run(inject_trim_2 cornell-mirrors 96x96 trim:2 4 trim --split-bytes 163840)
diff_run(inject_intersect_2 cornell-mirrors 96x96 intersect:2 4 intersect --split-bytes 163840)
diff_run(inject_hash_2 cornell-mirrors 96x96 hash:2 4 hash --max-groups 2)
# 300 small boxes as separate objects make CRSH's object mask (top nodes x objects) outgrow a
# 256 KiB binding at 128x128, so the mask is computed in parts and read by rows.
set(studs "[]")
foreach(i RANGE 299)
  math(EXPR x "40 + (${i} % 20) * 25")
  math(EXPR y "20 + (${i} / 20) * 8")
  string(JSON studs SET "${studs}" ${i} "{\"translate\": [${x}, ${y}, 300]}")
endforeach()
string(JSON studs_scene SET "${cornell}" objects 2 "{\"name\": \"studs\", \"generator\": \"box\", \"params\": {\"size\": 6}, \"material\": \"clay\", \"instances\": ${studs}}")
file(WRITE "${WORK}/studs-scene.json" "${studs_scene}")
diff_run(studs_paged "${WORK}/studs-scene.json" 128x128 "" 0 "" --split-bytes 262144)
# At depth 1 the mask (2,048 top nodes x 307 objects) outgrows even four such bindings: the top
# level binds only the mask rows of each dispatch's top nodes.
diff_run(studs_depth1 "${WORK}/studs-scene.json" 128x128 "" 0 "" --split-bytes 262144 --depth 1)
diff_run(inject_traverse_2 "${WORK}/studs-scene.json" 128x128 traverse:2 4 traverse --split-bytes 262144)
if(EXISTS "${DATA}/sponza_dabrovic/sponza.obj")
  diff_run(sponza sponza 128x128 "" 0 "")
  diff_run(sponza_rah sponza 128x128 "" 0 "" --algo rah)
endif()
foreach(f raster:1 surfaces:1 raygen.shadow:1 raygen.shadow:2 trim:1 hash:1 compress:1 sort:1 decompress:1 build:1
          traverse:1 reduce:1 intersect:1 shade:1 raygen.reflection:1 surfaces.hits:1 resolve:1)
  string(REPLACE ":" "_" n "${f}")
  string(REGEX REPLACE ":.*" "" pass "${f}")
  diff_run(inject_${n} cornell-mirrors 64x64 ${f} 4 ${pass})
endforeach()
# The scan-based reduction's fault needs the scan reduction.
diff_run(inject_reduce_2 cornell-mirrors 64x64 reduce:2 4 reduce --reduction scan)
diff_run(inject_traverse_rah cornell-mirrors 64x64 traverse:1 4 traverse --algo rah)

# Saved inputs replay to the same comparison: with the fault it diverges again ("reproduced"),
# without it the pass is equal, which differs from the recording (exit 5).
file(REMOVE_RECURSE "${WORK}/saved")
diff_run(save cornell-mirrors 64x64 traverse:1 4 traverse --save-inputs "${WORK}/saved")
file(GLOB saved_top "${WORK}/saved/*-traverse.L2.shadow.b0")
file(GLOB saved_raster "${WORK}/saved/*-raster")
function(replay_run name dir expect_rc expect_text)
  execute_process(COMMAND "${RAYSPACE}" replay "${dir}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL expect_rc OR NOT "${out}${err}" MATCHES "${expect_text}")
    set(failures "${failures}\nreplay ${name}: exit ${rc} (expected ${expect_rc}), output: ${out}${err}" PARENT_SCOPE)
  endif()
endfunction()
if(NOT saved_top OR NOT saved_raster)
  set(failures "${failures}\nsave: no saved traverse.L2.shadow.b0 or raster call under ${WORK}/saved")
else()
  replay_run(top_fault "${saved_top}" 4 "recorded comparison: reproduced" --inject traverse)
  replay_run(top_clean "${saved_top}" 5 "NOT reproduced")
  replay_run(raster "${saved_raster}" 0 "raster/prim: 4096 elements equal")
endif()
replay_run(missing "${WORK}/no-such-dir" 2 "pass.json: cannot open")
file(MAKE_DIRECTORY "${WORK}/bad-set")
file(WRITE "${WORK}/bad-set/pass.json" "{\"method\": \"traverse.top\", \"buffers\": {\"top\": {\"type\": \"cone_node\", \"count\": 3}}}")
file(WRITE "${WORK}/bad-set/top.bin" "short")
replay_run(truncated "${WORK}/bad-set" 2 "top.bin: 5 bytes, expected 3 elements of 48 bytes")

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
