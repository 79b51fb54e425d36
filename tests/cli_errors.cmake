# The CLI's error contract, run as
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch dir> -P cli_errors.cmake
# Every bad input must exit with code 2 and print exactly one line on stderr that names the input.
# One positive case renders the Cornell scene and checks the statistics file.
# All cases run; the failures are listed together at the end.
cmake_minimum_required(VERSION 3.19)  # string(JSON)

include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
cli_script_begin(cli_errors.cmake RAYSPACE SRC WORK)

# --- Inputs -------------------------------------------------------------------------------------
set(CAMERA [=["camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 45}]=])
set(IMAGE [=["image": {"width": 16, "height": 16}]=])
set(LIGHTS [=["lights": [{"position": [0, 4, 4]}]]=])

# A valid scene (used for the --size/--threads/--algo/--out cases).
file(WRITE "${WORK}/good.json" "{${CAMERA}, ${IMAGE}, ${LIGHTS}, \"objects\": [{\"generator\": \"box\"}]}\n")
# Malformed JSON: a stray comma on line 3.
file(WRITE "${WORK}/malformed.json" "{\n  ${CAMERA},\n  ${IMAGE},,\n  \"objects\": []\n}\n")
# A number that overflows a double while parsing.
file(WRITE "${WORK}/overflow.json"
     "{\"camera\": {\"eye\": [0, 0, 1e400], \"target\": [0, 0, 0], \"fov_y_deg\": 45}, ${IMAGE}, \"objects\": [{\"generator\": \"box\"}]}\n")
# A scene whose mesh does not exist.
file(WRITE "${WORK}/missing_mesh.json"
     "{${CAMERA}, ${IMAGE}, ${LIGHTS}, \"objects\": [{\"name\": \"ghost\", \"mesh\": \"meshes/ghost.obj\"}]}\n")
# A scene whose OBJ has a NaN coordinate on line 3.
file(WRITE "${WORK}/nan.obj" "v 0 0 0\nv 1 0 0\nv nan 0 0\nf 1 2 3\n")
file(WRITE "${WORK}/nan_mesh.json"
     "{${CAMERA}, ${IMAGE}, ${LIGHTS}, \"objects\": [{\"name\": \"tri\", \"mesh\": \"nan.obj\"}]}\n")
# A scene whose generator has a negative count.
file(WRITE "${WORK}/bad_param.json"
     "{${CAMERA}, ${IMAGE}, ${LIGHTS}, \"objects\": [{\"generator\": \"box\"}, {\"generator\": \"sphere\", \"params\": {\"segments\": -4}}]}\n")

# A value nested 100,000 deep (200 KB), a key given twice, a NUL byte after the closing brace.
string(REPEAT "[" 100000 open)
string(REPEAT "]" 100000 close)
file(WRITE "${WORK}/deep.json" "{${CAMERA}, ${IMAGE}, ${LIGHTS}, \"objects\": ${open}1${close}}\n")
file(WRITE "${WORK}/dup_key.json" "{${CAMERA}, ${IMAGE}, ${LIGHTS}, ${IMAGE}, \"objects\": [{\"generator\": \"box\"}]}\n")

# --- Error cases --------------------------------------------------------------------------------
expect_error(NAME "malformed scene JSON"
             NEEDLES "malformed.json" "line 3"
             ARGS render "${WORK}/malformed.json" --out "${WORK}/x.png")
expect_error(NAME "scene JSON number overflow (1e400)"
             NEEDLES "overflow.json"
             ARGS render "${WORK}/overflow.json" --out "${WORK}/x.png")
expect_error(NAME "scene JSON nested 100,000 deep" NEEDLES "deep.json: invalid JSON: nested deeper than 256"
             ARGS render "${WORK}/deep.json" --out "${WORK}/x.png")
expect_error(NAME "scene JSON with a key given twice" NEEDLES "dup_key.json: invalid JSON: the key \"image\" is given twice"
             ARGS render "${WORK}/dup_key.json" --out "${WORK}/x.png")
execute_process(COMMAND sh -c "cat \"$0\" && printf '\\000'" "${WORK}/good.json" OUTPUT_FILE "${WORK}/nul.json")
expect_error(NAME "scene JSON with a NUL byte after the closing brace" NEEDLES "nul.json: invalid JSON:" "a NUL byte"
             ARGS render "${WORK}/nul.json" --out "${WORK}/x.png")
expect_error(NAME "scene references a missing mesh"
             NEEDLES "missing_mesh.json" "objects[0].mesh" "meshes/ghost.obj" "--data"
             ARGS render "${WORK}/missing_mesh.json" --out "${WORK}/x.png")
expect_error(NAME "generator parameter out of range"
             NEEDLES "bad_param.json" "objects[1]: generator 'sphere': params.segments: -4 out of range [3, 4096]"
             ARGS render "${WORK}/bad_param.json" --out "${WORK}/x.png")
expect_error(NAME "missing scene file"
             NEEDLES "no_such_scene.json"
             ARGS render "${WORK}/no_such_scene.json" --out "${WORK}/x.png")
# The options are validated once, right after parsing, before the scene is read: a capacity too small
# for the hierarchy is named although the scene does not exist.
expect_error(NAME "--pair-capacity too small, checked before the scene is read"
             NEEDLES "--pair-capacity 10: too small for subdivision 8 with 3 levels"
             ARGS render "${WORK}/no_such_scene.json" --subdivision 8 --levels 3 --pair-capacity 10 --out "${WORK}/x.png")
expect_error(NAME "--size 0x10"
             NEEDLES "--size" "0x10"
             ARGS render "${WORK}/good.json" --size 0x10 --out "${WORK}/x.png")
expect_error(NAME "--size 99999x10"
             NEEDLES "--size" "99999x10"
             ARGS render "${WORK}/good.json" --size 99999x10 --out "${WORK}/x.png")
expect_error(NAME "--size abc"
             NEEDLES "--size" "abc"
             ARGS render "${WORK}/good.json" --size abc --out "${WORK}/x.png")
expect_error(NAME "--levels autox"
             NEEDLES "--levels" "autox" "not auto or an integer in [1 - 12]"
             ARGS render "${WORK}/good.json" --levels autox --out "${WORK}/x.png")
expect_error(NAME "--levels 13"
             NEEDLES "--levels" "'13'"
             ARGS render "${WORK}/good.json" --levels 13 --out "${WORK}/x.png")
expect_error(NAME "--threads 0"
             NEEDLES "--threads"
             ARGS render "${WORK}/good.json" --threads 0 --out "${WORK}/x.png")
expect_error(NAME "--split-bytes 100 (below one element of every buffer)"
             NEEDLES "--split-bytes" "100"
             ARGS render "${WORK}/good.json" --backend vulkan --split-bytes 100 --out "${WORK}/x.png")
expect_error(NAME "--path unknown"
             NEEDLES "--path"
             ARGS render "${WORK}/good.json" --path sideways --out "${WORK}/x.png")
expect_error(NAME "diff --path unknown"
             NEEDLES "--path" "sideways"
             ARGS diff "${WORK}/good.json" --path sideways)
expect_error(NAME "--objects unknown"
             NEEDLES "--objects" "bush"
             ARGS render "${WORK}/good.json" --objects bush --out "${WORK}/x.png")
expect_error(NAME "--tree-big nan"
             NEEDLES "--tree-big" "finite"
             ARGS render "${WORK}/good.json" --tree-big nan --out "${WORK}/x.png")
expect_error(NAME "--tree-leaf 0"
             NEEDLES "--tree-leaf" "0"
             ARGS render "${WORK}/good.json" --tree-leaf 0 --out "${WORK}/x.png")
expect_error(NAME "--max-groups 0"
             NEEDLES "--max-groups" "0"
             ARGS diff "${WORK}/good.json" --max-groups 0)
expect_error(NAME "--schedule sideways"
             NEEDLES "--schedule" "sideways" "forward, reverse or random"
             ARGS render "${WORK}/good.json" --schedule sideways --out "${WORK}/x.png")
expect_error(NAME "--schedule random:-1"
             NEEDLES "--schedule" "random:-1"
             ARGS diff "${WORK}/good.json" --schedule random:-1)
expect_error(NAME "--inject trim:no-such-fault"
             NEEDLES "--inject" "trim:no-such-fault" "dropped-barrier"
             ARGS diff "${WORK}/good.json" --inject trim:no-such-fault)
expect_error(NAME "--inject trim:1@emu (a fault the emulator does not have)"
             NEEDLES "--inject" "trim:1@emu" "workgroup faults"
             ARGS diff "${WORK}/good.json" --inject trim:1@emu)
expect_error(NAME "--inject trim:global-race@emu (a fault of the kernel alone)"
             NEEDLES "--inject" "trim:global-race@emu" "live in the kernel alone"
             ARGS diff "${WORK}/good.json" --inject trim:global-race@emu)
expect_error(NAME "--sim-checks with a checker that does not exist"
             NEEDLES "--sim-checks" "'bogus' is not a checker"
             ARGS diff "${WORK}/good.json" --backends emu,sim --sim-checks racecheck,bogus)
expect_error(NAME "--sim-checks for a Vulkan device"
             NEEDLES "--sim-checks racecheck" "only the simulated GPU runs these checkers"
             ARGS diff "${WORK}/good.json" --backends emu,vulkan --sim-checks racecheck)
expect_error(NAME "--inject trim:dropped-barrier@gpu"
             NEEDLES "--inject" "'emu'"
             ARGS diff "${WORK}/good.json" --inject trim:dropped-barrier@gpu)
expect_error(NAME "--inject-each with a fault that does not exist"
             NEEDLES "--inject-each 'bogus:3'" "no kernel named 'bogus'"
             ARGS diff "${WORK}/good.json" --inject-each trim:1,bogus:3)
expect_error(NAME "--inject-each beside --inject"
             NEEDLES "--inject-each" "not both"
             ARGS diff "${WORK}/good.json" --inject-each trim:1 --inject trim:2)
expect_error(NAME "--inject-each with --save-inputs"
             NEEDLES "--inject-each" "--save-inputs"
             ARGS diff "${WORK}/good.json" --inject-each trim:1 --save-inputs "${WORK}/saved-each")
# `rayspace export`: a saved call, an output directory that is new or empty, and a pass it can
# replay with compute dispatches. Every refusal leaves no output directory behind.
execute_process(COMMAND "${RAYSPACE}" diff "${WORK}/good.json" --size 8x8 --save-inputs "${WORK}/saved"
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err TIMEOUT 120)
if(NOT rc EQUAL 0)
  set(FAILURES "${FAILURES}\n  [export] diff --save-inputs: exit ${rc}: ${err}")
endif()
file(GLOB saved_trim LIST_DIRECTORIES true "${WORK}/saved/*-trim.shadow.b0")
file(GLOB saved_raster LIST_DIRECTORIES true "${WORK}/saved/*-raster")
file(MAKE_DIRECTORY "${WORK}/empty-dir" "${WORK}/full-dir")
file(WRITE "${WORK}/full-dir/keep.txt" "not the export's\n")
expect_error(NAME "export: a saved call that does not exist"
             NEEDLES "${WORK}/no-such-call" "no such directory"
             ARGS export "${WORK}/no-such-call" --out "${WORK}/export-1")
expect_error(NAME "export: a directory that is not a saved call"
             NEEDLES "${WORK}/empty-dir" "not a call saved by diff --save-inputs"
             ARGS export "${WORK}/empty-dir" --out "${WORK}/export-2")
expect_error(NAME "export: the directory of all saved calls"
             NEEDLES "${WORK}/saved" "a directory of saved calls, not one call"
             ARGS export "${WORK}/saved" --out "${WORK}/export-3")
expect_error(NAME "export: a file as the saved call"
             NEEDLES "${WORK}/good.json" "not a directory"
             ARGS export "${WORK}/good.json" --out "${WORK}/export-4")
expect_error(NAME "export --out a non-empty directory"
             NEEDLES "--out" "${WORK}/full-dir" "not empty"
             ARGS export "${saved_trim}" --out "${WORK}/full-dir")
expect_error(NAME "export --out an existing file"
             NEEDLES "--out" "${WORK}/full-dir/keep.txt" "not a directory"
             ARGS export "${saved_trim}" --out "${WORK}/full-dir/keep.txt")
expect_error(NAME "export without --out"
             NEEDLES "--out"
             ARGS export "${saved_trim}")
expect_error(NAME "export of the raster (a graphics pipeline)"
             NEEDLES "${saved_raster}" "pass raster cannot be exported" "graphics pipeline"
             ARGS export "${saved_raster}" --out "${WORK}/export-5")
expect_error(NAME "export --inject of an unknown pass"
             NEEDLES "--inject" "nope:1"
             ARGS export "${saved_trim}" --out "${WORK}/export-6" --inject nope:1)
expect_error(NAME "export --device 63"
             NEEDLES "--device 63"
             ARGS export "${saved_trim}" --out "${WORK}/export-7" --device 63)
file(COPY "${saved_trim}/" DESTINATION "${WORK}/bad-comparison")
file(WRITE "${WORK}/bad-comparison/comparison.json" "{\"options\": {\"local_size\": -3}}")
expect_error(NAME "export of a call whose comparison.json is malformed"
             NEEDLES "${WORK}/bad-comparison/comparison.json" "local_size"
             ARGS export "${WORK}/bad-comparison" --out "${WORK}/export-8")
foreach(i RANGE 1 8)
  if(EXISTS "${WORK}/export-${i}")
    set(FAILURES "${FAILURES}\n  [export] a refused export left ${WORK}/export-${i} behind")
  endif()
endforeach()
file(GLOB partial "${WORK}/*.partial-*")
if(partial OR NOT EXISTS "${WORK}/full-dir/keep.txt")
  set(FAILURES "${FAILURES}\n  [export] a refused export left '${partial}' behind or touched --out")
endif()
# --validate without the validation layer (the loader searches an empty layer path).
file(MAKE_DIRECTORY "${WORK}/no-layers")
set(ENV{VK_LAYER_PATH} "${WORK}/no-layers")
expect_error(NAME "--validate without the layer"
             NEEDLES "--validate" "VK_LAYER_KHRONOS_validation" "vulkan-validationlayers"
             ARGS render "${WORK}/good.json" --backend vulkan --validate --out "${WORK}/x.png")
unset(ENV{VK_LAYER_PATH})
expect_error(NAME "--algo nope"
             NEEDLES "--algo" "nope"
             ARGS render "${WORK}/good.json" --algo nope --out "${WORK}/x.png")
expect_error(NAME "--hash-order nope"
             NEEDLES "--hash-order" "nope"
             ARGS render "${WORK}/good.json" --hash-order nope --out "${WORK}/x.png")
expect_error(NAME "--hash-bits past the key"
             NEEDLES "--hash-bits" "15"
             ARGS diff "${WORK}/good.json" --hash-bits 15)
expect_error(NAME "bench --hash-bits 0"
             NEEDLES "--hash-bits" "0"
             ARGS bench "${WORK}/good.json" --hash-bits 0)
expect_error(NAME "bench --configs with an unknown configuration"
             NEEDLES "--configs" "warp" "crsh-passes"
             ARGS bench "${WORK}/good.json" --configs embree,warp)
expect_error(NAME "bench --sizes with a bad size"
             NEEDLES "--sizes" "0x3"
             ARGS bench "${WORK}/good.json" --sizes 16x16,0x3)
expect_error(NAME "bench --sizes abc"
             NEEDLES "--sizes" "abc"
             ARGS bench "${WORK}/good.json" --sizes abc)
expect_error(NAME "bench with a missing scene file (after a good one)"
             NEEDLES "no_such_scene.json"
             ARGS bench "${WORK}/good.json" "${WORK}/no_such_scene.json" --sizes 8x8)
expect_error(NAME "OBJ mesh with a NaN coordinate"
             NEEDLES "nan.obj:3:"
             ARGS render "${WORK}/nan_mesh.json" --out "${WORK}/x.png")
expect_error(NAME "unwritable --out (directory does not exist)"
             NEEDLES "${WORK}/no_such_dir/out.png"
             ARGS render "${WORK}/good.json" --out "${WORK}/no_such_dir/out.png")
if(EXISTS "${WORK}/x.png")
  set(FAILURES "${FAILURES}\n  [error cases] an output image was written although every case failed")
endif()

# --- Positive case ------------------------------------------------------------------------------
math(EXPR CASES "${CASES} + 1")
execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 32x32
                        --out "${WORK}/c.png" --stats "${WORK}/c.json"
                WORKING_DIRECTORY "${WORK}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                TIMEOUT 300)
set(positive "render cornell-mirrors 32x32")
if(NOT "${rc}" STREQUAL "0")
  set(FAILURES "${FAILURES}\n  [${positive}] exit code '${rc}', expected 0\n    stdout: ${out}\n    stderr: ${err}")
elseif(NOT EXISTS "${WORK}/c.png")
  set(FAILURES "${FAILURES}\n  [${positive}] no image at ${WORK}/c.png")
elseif(NOT EXISTS "${WORK}/c.json")
  set(FAILURES "${FAILURES}\n  [${positive}] no statistics file at ${WORK}/c.json")
else()
  file(READ "${WORK}/c.json" stats)
  string(JSON width ERROR_VARIABLE jerr GET "${stats}" width)
  if(jerr)
    set(FAILURES "${FAILURES}\n  [${positive}] stats: cannot read 'width': ${jerr}")
  elseif(NOT width EQUAL 32)
    set(FAILURES "${FAILURES}\n  [${positive}] stats: width is '${width}', expected 32")
  endif()
  string(JSON height ERROR_VARIABLE jerr GET "${stats}" height)
  if(jerr OR NOT height EQUAL 32)
    set(FAILURES "${FAILURES}\n  [${positive}] stats: height is '${height}' (${jerr}), expected 32")
  endif()
  string(JSON mismatches ERROR_VARIABLE jerr GET "${stats}" oracle mismatches)
  if(jerr)
    set(FAILURES "${FAILURES}\n  [${positive}] stats: cannot read 'oracle.mismatches': ${jerr}")
  else()
    # Either a count or a list of mismatching rays: both must be empty / zero.
    string(JSON mtype TYPE "${stats}" oracle mismatches)
    if(mtype STREQUAL "ARRAY")
      string(JSON mcount LENGTH "${stats}" oracle mismatches)
    else()
      set(mcount "${mismatches}")
    endif()
    if(NOT mcount EQUAL 0)
      set(FAILURES "${FAILURES}\n  [${positive}] stats: oracle.mismatches is '${mismatches}', expected 0")
    endif()
  endif()
  if(NOT FAILURES MATCHES "\\[${positive}\\]")
    message(STATUS "ok: ${positive}: width ${width}, oracle.mismatches ${mismatches}")
  endif()
endif()

cli_script_end(cli.errors)
