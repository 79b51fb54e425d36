# `rayspace render --backend vulkan` gives the same digest and the same PNG bytes as `--backend emu`
# on the bundled scenes (reduced sizes), with bounces, refraction, forced dispatch splitting and
# paging, launches folded into rows (the configurations the diffs do not cover on render's path).
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DDATA=<data root> -DWORK=<scratch> [-DPART=sponza] -P cli_backend.cmake
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
set(failures "")
file(MAKE_DIRECTORY "${WORK}")

include("${CMAKE_CURRENT_LIST_DIR}/cli_same_frame.cmake")

# PART=sponza: only the Sponza frames (test cli.backend.sponza), which need the data root; without it
# they print "data root not found" and ctest counts them as skipped (SKIP_REGULAR_EXPRESSION).
# PART=office: office's frames (test cli.backend.office, full tier). Each: crsh and rah.
if(PART STREQUAL "sponza" OR PART STREQUAL "office")
  set(size 64x64)
  if(PART STREQUAL "sponza")
    cli_require_data(cli.backend.sponza)
    set(size 128x128)
  endif()
  same_frame(${PART} "${SRC}/scenes/${PART}.json" ${size})
  same_frame(${PART}_rah "${SRC}/scenes/${PART}.json" ${size} --algo rah)
  if(failures)
    message(FATAL_ERROR "render --backend vulkan differs from emu:${failures}")
  endif()
  return()
endif()

set(cornell "${SRC}/scenes/cornell-mirrors.json")
# The render command's own path on each backend (fused traversal by default). Configurations whose
# every pass a default-tier diff compares bitwise on the path render takes are not repeated here:
# rah and rah-quadtree (cli.diff.cornell.rah, office.rah.fused, cornell.rah-quadtree.fused), the
# traversal lists with culling, heads and the frustum (cli.diff.cornell.tl.*), brute
# (cli.diff.cornell.brute), the scan reduction, paged or not (cli.diff.cornell.crsh.scan,
# .scan.paged).
foreach(algo crsh embree)
  same_frame(cornell_${algo} "${cornell}" 64x48 --algo ${algo})
endforeach()
same_frame(cornell_sub4_d3 "${cornell}" 64x48 --subdivision 4 --depth 3)
# Bindings far smaller than maxStorageBufferRange: per-pixel and per-ray buffers run in parts or
# are paged over several bindings, pair streams split, and launches fold into rows of workgroups.
# The split counts are the passes' (traverse's slots and reduce's streams split most); the fused
# path's traverse.compact splits by rows and pairs too (cornell_split_fused).
same_frame(cornell_paged "${cornell}" 96x80 --split-bytes 131072 --path passes)
same_frame(cornell_split "${cornell}" 48x40 --split-bytes 65536 --path passes)
same_frame(cornell_split_fused "${cornell}" 48x40 --split-bytes 65536 --path fused)
same_frame(cornell_rows "${cornell}" 64x48 --max-groups 3)
same_frame(cornell_capacity "${cornell}" 96x80 --pair-capacity 3000)
foreach(run_min cornell_paged:100 cornell_split:100 cornell_split_fused:20)
  string(REGEX REPLACE ":.*" "" run "${run_min}")
  string(REGEX REPLACE ".*:" "" min "${run_min}")
  file(READ "${WORK}/${run}_vulkan.json" j)
  string(JSON splits GET "${j}" backend split_dispatches)
  string(JSON paged GET "${j}" backend paged_arrays)
  if(splits LESS min OR paged LESS 10)
    set(failures "${failures}\n${run}: ${splits} split dispatches, ${paged} paged arrays; the split and paging paths did not run")
  endif()
endforeach()

file(READ "${cornell}" c)
string(JSON glass SET "${c}" materials clay transparency 0.5)
string(JSON glass SET "${glass}" materials clay ior 1.5)
file(WRITE "${WORK}/glass-scene.json" "${glass}")
foreach(algo crsh rah)
  same_frame(glass_${algo} "${WORK}/glass-scene.json" 80x64 --algo ${algo})
endforeach()


# A frame whose rays outgrow every page, or a scene array beyond one binding, is refused up front
# as bad input (exit 2, one line): with the device's own limit, and with lowered ones.
function(refused name pattern)
  execute_process(COMMAND "${RAYSPACE}" render "${cornell}" --backend vulkan --no-oracle --out "${WORK}/refused.png" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "^rayspace: error: ${pattern}")
    set(failures "${failures}\n${name}: exit ${rc}, stderr '${err}'" PARENT_SCOPE)
  endif()
endfunction()
refused(oversized_frame "--size 3000x3000: 9000000 rays per batch \\(1 light sample\\(s\\)\\) exceed the [0-9]+ that 4 bindings"
        --size 3000x3000)
refused(frame_beyond_lowered_limit
        "--size 128x128: 16384 rays per batch \\(1 light sample\\(s\\)\\) exceed the 4096 that 4 bindings of 65536 bytes hold on .*; at most 4096 pixels fit"
        --size 128x128 --split-bytes 65536)
refused(scene_beyond_lowered_limit
        "scene: 828 triangles take 39744 bytes per triangle array, more than one binding of .* holds \\(16384 bytes\\)"
        --size 8x8 --split-bytes 16384)

if(failures)
  message(FATAL_ERROR "render --backend vulkan differs from emu:${failures}")
endif()
