# `render --algo grid` (docs/grids.md) on the bundled scenes at reduced sizes: exit 0, no oracle
# mismatch, the same PNG bytes as --algo crsh; statistics in which every point-light shadow ray visits
# one perspective cell and an area light's walk its 3D perspective grid; the Vulkan kernel's digest and
# PNG equal to the emulator's. The data-free scenes by default; -DPART=data those that need the data
# root (skipped without it), and conference's build diffed pass by pass.
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DDATA=<data root> -DWORK=<scratch> [-DPART=data] -P cli_grid.cmake
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/cli_same_frame.cmake)
set(failures "")
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")

# same_as_crsh(NAME SCENE SIZE [grid options...]): --algo grid with the oracle, then --algo crsh.
function(same_as_crsh name scene size)
  foreach(algo grid crsh)
    set(extra "")
    if(algo STREQUAL "grid")
      set(extra ${ARGN})
    endif()
    execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/${scene}.json" --data "${DATA}" --size ${size} --algo ${algo} ${extra}
                            --out "${WORK}/${name}.${algo}.png" --stats "${WORK}/${name}.${algo}.json"
                    RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      set(failures "${failures}\n${name} (${algo}): exit ${rc}: ${err}" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  file(READ "${WORK}/${name}.grid.json" j)
  string(JSON mism GET "${j}" oracle mismatches)
  file(SHA256 "${WORK}/${name}.grid.png" a)
  file(SHA256 "${WORK}/${name}.crsh.png" b)
  if(NOT mism EQUAL 0 OR NOT a STREQUAL b)
    set(failures "${failures}\n${name}: ${mism} oracle mismatches, PNG equal to crsh's: ${a} vs ${b}" PARENT_SCOPE)
  endif()
endfunction()

if(PART STREQUAL "data")
  cli_require_data(cli.grid.data bunny/bun_zipper_res4.ply dragon/dragon.obj)
  same_as_crsh(sponza sponza 96x96)
  same_as_crsh(dragon dragon-closeup 64x64 --grid-regular 128)
  same_as_crsh(bunny roger-bunny-res4 64x64)
  same_as_crsh(suzanne toczek-suzanne 64x64 --grid-cells 50)
  same_as_crsh(sponza-soft sponza-soft 48x48)
  # The build as kernels, pass by pass: conference has triangles with two equal vertices, whose least
  # distance was 0 / 0 (a NaN grid.cells refused as its input).
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/conference.json" --data "${DATA}" --size 32x32 --algo grid --no-impact
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "\n  all passes equal\n")
    set(failures "${failures}\nconference diff --algo grid: exit ${rc}, expected all passes equal: ${out}${err}")
  endif()
else()
  same_as_crsh(cornell cornell-mirrors 96x96)
  same_as_crsh(soft cornell-soft 64x64)
  same_as_crsh(soft-coarse cornell-soft 48x48 --grid-area 8x8x3 --grid-area-near 1)
  same_as_crsh(soft-regular cornell-soft 48x48 --grid-area regular)
  same_as_crsh(secondary cornell-mirrors 64x64 --grid-secondary perspective)
  same_as_crsh(office office 96x96 --grid-cells 100)
  same_as_crsh(wavy roger-wavy-n8 64x64 --grid-regular 8)
  same_as_crsh(cubes toczek-cubes 64x64)
  if(NOT failures)
    # The area light's shadow rays all walk its 3D grid, or none (--grid-area regular); with
    # --grid-secondary perspective every reflection ray walks the eye's.
    foreach(c soft soft-regular)
      file(READ "${WORK}/${c}.grid.json" j)
      string(JSON rays GET "${j}" grids per_type shadow area_light_rays rays)
      string(JSON through GET "${j}" grids per_type shadow area_light_rays through_3d_perspective_grid)
      if(rays EQUAL 0 OR (c STREQUAL "soft" AND NOT through EQUAL rays) OR (c STREQUAL "soft-regular" AND NOT through EQUAL 0))
        set(failures "${failures}\n${c}: ${through} of ${rays} area-light shadow rays through a 3D perspective grid")
      endif()
    endforeach()
    file(READ "${WORK}/secondary.grid.json" j)
    string(JSON rays GET "${j}" grids per_type reflection rays)
    string(JSON through GET "${j}" grids per_type reflection through_3d_perspective_grid)
    if(rays EQUAL 0 OR NOT through EQUAL rays)
      set(failures "${failures}\nsecondary: ${through} of ${rays} reflection rays through the eye's 3D perspective grid")
    endif()
    # The mirrors' point light: one perspective cell per shadow ray, every shadow ray through it;
    # reflections step through several regular cells.
    file(READ "${WORK}/cornell.grid.json" j)
    string(JSON steps GET "${j}" grids per_type shadow steps_per_ray)
    string(JSON rays GET "${j}" grids per_type shadow rays)
    string(JSON persp GET "${j}" grids per_type shadow perspective_rays)
    string(JSON skipped GET "${j}" grids per_type shadow rays_without_tests)
    string(JSON refl GET "${j}" grids per_type reflection steps_per_ray)
    if(NOT steps EQUAL 1 OR NOT persp EQUAL rays OR skipped EQUAL 0 OR NOT refl GREATER 1)
      set(failures "${failures}\ncornell: shadow ${steps} cells per ray, ${persp} of ${rays} through the light's grid, "
                   "${skipped} without a test; reflection ${refl} cells per ray")
    endif()
    # An area light has no perspective grid here: its shadow rays step through the regular grid.
    file(READ "${WORK}/soft.grid.json" j)
    string(JSON persp ERROR_VARIABLE none GET "${j}" grids per_type shadow perspective_rays)
    string(JSON steps GET "${j}" grids per_type shadow steps_per_ray)
    if(none STREQUAL "NOTFOUND" OR NOT steps GREATER 1)
      set(failures "${failures}\nsoft: area-light shadow rays through a perspective grid (${persp}), ${steps} cells per ray")
    endif()
  endif()
  # --closed-models: the mirrors' box and ball are closed (no warning); most unoccluded shadow rays
  # need no test; the shadow results culling changes are counted, not failed. The cubes scene's
  # floor and walls are open, and each is named.
  execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 64x64 --algo grid --closed-models
                          --out "${WORK}/closed.png" --stats "${WORK}/closed.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR err MATCHES "warning" OR NOT out MATCHES "culling     --closed-models changed [0-9]+ shadow results")
    set(failures "${failures}\nclosed: exit ${rc}, ${out}${err}")
  else()
    file(READ "${WORK}/closed.json" j)
    string(JSON changes GET "${j}" oracle shadow_changes)
    string(JSON spared GET "${j}" grids per_type shadow unoccluded_without_tests_fraction)
    string(JSON closed_flag GET "${j}" tracer closed_models)
    if(NOT closed_flag OR changes GREATER 50 OR spared LESS 0.9)
      set(failures "${failures}\nclosed: closed_models ${closed_flag}, ${changes} shadow results changed, ${spared} of the unoccluded spared")
    endif()
  endif()
  execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/toczek-cubes.json" --size 32x32 --algo grid --closed-models --no-oracle
                          --out "${WORK}/cubes-closed.png" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT err MATCHES "warning: --closed-models: object 18 'floor' is not closed"
     OR err MATCHES "object 0 ")
    set(failures "${failures}\ncubes-closed: exit ${rc}, ${err}")
  endif()
  # --primary grid: an eye ray per pixel through the eye's grid, one cell each, checked by the oracle
  # (0 mismatches above all) and compared with the raster's primitives; refused with another tracer.
  execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 64x64 --algo grid --primary grid
                          --out "${WORK}/primary.png" --stats "${WORK}/primary.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    set(failures "${failures}\nprimary: exit ${rc}, ${out}${err}")
  else()
    file(READ "${WORK}/primary.json" j)
    string(JSON mism GET "${j}" oracle mismatches)
    string(JSON rays GET "${j}" primary rays)
    string(JSON steps GET "${j}" grids per_type primary steps_per_ray)
    string(JSON persp GET "${j}" grids per_type primary perspective_rays)
    if(NOT mism EQUAL 0 OR NOT rays EQUAL 4096 OR NOT steps EQUAL 1 OR NOT persp EQUAL 4096)
      set(failures "${failures}\nprimary: ${mism} mismatches, ${rays} eye rays, ${steps} cells per eye ray, ${persp} through the eye's grid")
    endif()
  endif()
  execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --primary grid --out "${WORK}/x.png"
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "--primary grid: only --algo grid")
    set(failures "${failures}\n--primary grid with crsh: exit ${rc}, ${err}")
  endif()
  # The Vulkan kernel: the emulator's digest and PNG (the emulator's render path tests cells' triangles
  # in SIMD lanes; --path passes runs grid.trace ray by ray, as diff does: the same digest).
  set(DATA "")
  render_digest(d_lanes lanes "${SRC}/scenes/cornell-soft.json" 40x40 emu --algo grid --primary grid --grid-cells 30)
  render_digest(d_pass pass "${SRC}/scenes/cornell-soft.json" 40x40 emu --algo grid --primary grid --grid-cells 30 --path passes)
  if(d_lanes STREQUAL "" OR NOT d_lanes STREQUAL d_pass)
    set(failures "${failures}\nlanes vs --path passes: digest '${d_lanes}' vs '${d_pass}'")
  endif()
  same_frame(vulkan-cornell "${SRC}/scenes/cornell-mirrors.json" 64x64 --algo grid)
  same_frame(vulkan-soft "${SRC}/scenes/cornell-soft.json" 48x48 --algo grid --grid-cells 40)
  same_frame(vulkan-closed "${SRC}/scenes/cornell-mirrors.json" 48x48 --algo grid --closed-models)
  # Office's 36,312 triangles span nine scan blocks of the grid build; 32 cells a side keep its 3.6 M
  # cell references of the default grids (7.7 s on lavapipe) to 355,078 (2.1 s).
  same_frame(vulkan-primary "${SRC}/scenes/office.json" 48x40 --algo grid --primary grid --grid-cells 32 --grid-regular 32)
  # shadow-bench: one table row per scene and the same numbers as JSON; a scene without a point light
  # is refused naming it.
  execute_process(COMMAND "${RAYSPACE}" shadow-bench "${SRC}/scenes/cornell-mirrors.json" "${SRC}/scenes/office.json" --size 32x32
                          --repetitions 1 --json "${WORK}/shadow-bench.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "cornell-mirrors +828 +[0-9]+" OR NOT out MATCHES "office +36312 +2048")
    set(failures "${failures}\nshadow-bench: exit ${rc}: ${out}${err}")
  else()
    file(READ "${WORK}/shadow-bench.json" j)
    string(JSON rays GET "${j}" scenes 1 rays)
    string(JSON grid_rate GET "${j}" scenes 1 grid_rays_per_s)
    string(JSON differing GET "${j}" scenes 0 differing)
    if(NOT rays EQUAL 2048 OR NOT grid_rate GREATER 0 OR NOT differing EQUAL 0)
      set(failures "${failures}\nshadow-bench JSON: ${rays} rays, ${grid_rate} rays/s, ${differing} differing")
    endif()
  endif()
  execute_process(COMMAND "${RAYSPACE}" shadow-bench "${SRC}/scenes/cornell-soft.json" --size 16x16 --repetitions 1
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "cornell-soft.json: no point light")
    set(failures "${failures}\nshadow-bench on area lights only: exit ${rc}, ${err}")
  endif()
  # Bad grid sizes are refused naming the option.
  foreach(bad "--grid-cells;0" "--grid-regular;2000" "--grid-area;200x100x4" "--grid-area;abc" "--grid-area;1024x1024x64"
              "--grid-area-near;0" "--grid-secondary;bvh")
    execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --algo grid ${bad} --out "${WORK}/x.png"
                    RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
    list(GET bad 0 flag)
    if(rc EQUAL 0 OR NOT err MATCHES "${flag}")
      set(failures "${failures}\n${bad}: exit ${rc}, ${err}")
    endif()
  endforeach()
endif()
if(failures)
  message(FATAL_ERROR "cli.grid:${failures}")
endif()
message(STATUS "cli.grid: every scene traced through the grids as through the hierarchy")
