# `rayspace data check`: a copy of Sponza's files passes; a truncated, a modified and a missing file
# each give a one-line problem naming the file, what differs and where to get it, and exit 2; the
# real data root passes for every bundled scene; scenes/manifest.json is what
# scripts/make_manifest.py writes from it. Needs the data root (skipped without it).
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DDATA=<data root> -DWORK=<scratch> -P cli_data.cmake
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
cli_require_data(cli.data bunny/bun_zipper.ply bunny/bun_zipper_res2.ply bunny/bun_zipper_res3.ply bunny/bun_zipper_res4.ply)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/root/sponza_dabrovic")
set(failures "")

# Runs `data check ARGN` and expects exit `want` and output matching `regex`.
function(expect name want regex)
  execute_process(COMMAND "${RAYSPACE}" data check ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL want OR NOT "${out}${err}" MATCHES "${regex}")
    set(failures "${failures}\n${name}: exit ${rc} (want ${want}), output does not match '${regex}':\n${out}${err}" PARENT_SCOPE)
  endif()
endfunction()

set(root "${WORK}/root")
set(mtl "${root}/sponza_dabrovic/sponza.mtl")
file(COPY "${DATA}/sponza_dabrovic/sponza.obj" "${DATA}/sponza_dabrovic/sponza.mtl" DESTINATION "${root}/sponza_dabrovic")
expect(copy 0 "sponza.json: ok" sponza --data "${root}")
expect(scene-file 0 "sponza.json: ok" "${SRC}/scenes/sponza.json" --data "${root}")
# A scene file of the user's is loaded as render would: "ok" means it renders, so a width of 0 is a problem.
file(READ "${SRC}/scenes/cornell-mirrors.json" cornell)
string(JSON zero SET "${cornell}" image width 0)
file(WRITE "${WORK}/zero-width.json" "${zero}")
expect(zero-width 2 "zero-width.json: problem: [^\n]*image.width" "${WORK}/zero-width.json" --data "${root}")
set(url "https://github.com/jonike/mnrt/blob/[0-9a-f]+/Test%20Scenes/Sponza/sponza.3ds")

# Truncated: the size differs.
file(READ "${mtl}" text)
string(SUBSTRING "${text}" 0 100 head)
file(WRITE "${mtl}" "${head}")
expect(truncated 2 "sponza.json: problem: sponza_dabrovic/sponza.mtl: 100 bytes, the manifest says 3688 \\(converted from ${url}" sponza --data "${root}")

# Same size, one byte changed: the SHA-256 differs.
string(SUBSTRING "${text}" 1 -1 tail)
file(WRITE "${mtl}" "X${tail}")
expect(modified 2 "sponza_dabrovic/sponza.mtl: SHA-256 [0-9a-f]+, the manifest says 7bf25f78[0-9a-f]+: a different file" sponza --data "${root}")
expect(modified-exit-line 2 "rayspace: error: data check: 1 problem \\(files missing or different under" sponza --data "${root}")

# Missing.
file(REMOVE "${mtl}")
expect(missing 2 "sponza_dabrovic/sponza.mtl: missing under the data root ${root}" sponza --data "${root}")

# Bad arguments.
expect(unknown-scene 2 "rayspace: error: data check: scene 'nonesuch' is neither a file nor a bundled scene" nonesuch --data "${root}")
expect(no-root-dir 2 "--data ${WORK}/none: not a directory" --data "${WORK}/none")

# The real data root: every bundled scene.
expect(real 0 "conference-soft.json: ok\nconference.json: ok\ncornell-mirrors.json: ok\ncornell-soft.json: ok\ndragon-closeup.json: ok\noffice.json: ok\nroger-bunny-full.json: ok\nroger-bunny-res2.json: ok\nroger-bunny-res3-room40.json: ok\nroger-bunny-res3.json: ok\nroger-bunny-res4.json: ok\nroger-sphere-room40.json: ok\nroger-sphere.json: ok\nroger-walls.json: ok\nroger-wavy-n16.json: ok\nroger-wavy-n32.json: ok\nroger-wavy-n4.json: ok\nroger-wavy-n8.json: ok\nsponza-glass.json: ok\nsponza-soft.json: ok\nsponza-thesis-fit-2.json: ok\nsponza-thesis-fit.json: ok\nsponza-thesis.json: ok\nsponza.json: ok\ntoczek-bunny-noground.json: ok\ntoczek-bunny.json: ok\ntoczek-cubes.json: ok\ntoczek-dragon.json: ok\ntoczek-suzanne.json: ok" --data "${DATA}")

# The manifest is current.
find_program(PYTHON3 python3 REQUIRED)
execute_process(COMMAND "${PYTHON3}" "${SRC}/scripts/make_manifest.py" --data "${DATA}" --scenes "${SRC}/scenes"
                        --check "${SRC}/scenes/manifest.json" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  set(failures "${failures}\nscenes/manifest.json is not what make_manifest.py writes: ${out}${err}")
endif()

if(failures)
  message(FATAL_ERROR "cli.data:${failures}")
endif()
message(STATUS "cli.data: copy ok; truncated, modified, missing each exit 2 naming the file; real data root ok")
