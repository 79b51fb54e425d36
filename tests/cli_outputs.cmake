# The CLI's outputs (images, statistics, bench JSON, the accuracy report), run as
#   cmake -DRAYSPACE=<exe> -DWORK=<scratch dir> -P cli_outputs.cmake
# An output that cannot be written is bad input found before the work: exit 2, one line on stderr
# naming the path, and nothing left behind (no image of the failed run, no temporary file). A write
# that fails late (a file size limit) leaves nothing either. "-" is standard output; an output may not
# replace an input; paths that are not UTF-8 are escaped in JSON; a signal leaves no temporary file.
# The diff's and replay's outputs are cases of cli_diff.cmake (they need Vulkan).
cmake_minimum_required(VERSION 3.19)  # string(JSON)

include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
cli_script_begin(cli_outputs.cmake RAYSPACE WORK)

set(SCENE [=[{"camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 45}, "image": {"width": 16, "height": 16}, "lights": [{"position": [0, 4, 4]}], "objects": [{"generator": "box"}]}]=])
file(WRITE "${WORK}/good.json" "${SCENE}\n")
file(WRITE "${WORK}/tri.obj" "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
string(REPLACE [=[{"generator": "box"}]=] [=[{"name": "tri", "mesh": "tri.obj"}]=] mesh_scene "${SCENE}")
file(WRITE "${WORK}/mesh.json" "${mesh_scene}\n")
file(WRITE "${WORK}/afile" "")
file(CREATE_LINK "${WORK}/target.json" "${WORK}/dangling.json" SYMBOLIC)

# fails(NAME needle ARGS...): render with ARGS (an output among them) must fail at once, leaving no x.png.
macro(fails name needle)
  expect_error(NAME "${name}" NEEDLES "${needle}" ABSENT "${WORK}/x.png" ARGS render "${WORK}/good.json" --out "${WORK}/x.png" ${ARGN})
endmacro()

# --- Outputs that cannot be written -----------------------------------------------------------
fails("--stats in a missing directory" "nodir/s.json: cannot write the statistics file" --stats "${WORK}/nodir/s.json")
# Tests run as root, for whom a chmod'ed read-only directory stays writable: a path under a regular
# file stands in for a directory where no file can be created.
fails("--stats under a regular file" "afile/s.json: cannot write the statistics file: Not a directory"
      --stats "${WORK}/afile/s.json")
fails("--stats on a full device" "/dev/full: cannot write the statistics file: is not a regular file" --stats /dev/full)
fails("--stats on a dangling symbolic link" "dangling.json: cannot write the statistics file: is a dangling symbolic link"
      --stats "${WORK}/dangling.json")
if(EXISTS "${WORK}/target.json")
  set(FAILURES "${FAILURES}\n  [dangling symbolic link] the link's target was created")
endif()
fails("--stats and --out naming one file" "given as the output image and as the statistics file" --stats "${WORK}/x.png")
# Checked before the backend: with --device 63 (no such device) as the next error, the message must
# name the output, not the device.
foreach(out result result.xyz /dev/null)
  expect_error(NAME "--out ${out} (no image format)" NEEDLES "${out}: cannot write an image in this format"
               ABSENT "${WORK}/result" "${WORK}/result.xyz"
               ARGS render "${WORK}/good.json" --out "${out}" --backend vulkan --device 63)
endforeach()
expect_error(NAME "--stats checked before the backend" NEEDLES "nodir/s.json"
             ARGS render "${WORK}/good.json" --out "${WORK}/x.png" --stats "${WORK}/nodir/s.json" --backend vulkan --device 63)

# --- Outputs an input or a spelling must not steer --------------------------------------------
# A scene's "name" names the default image only as a plain file name: a path, "..", "" or a control
# character is refused, naming the scene file, and nothing is written anywhere (WORK/sub is the
# working directory, so "../escaped" would land in WORK).
file(MAKE_DIRECTORY "${WORK}/sub")
foreach(bad "../escaped" "${WORK}/abs" "" ".." "a\tb")
  string(JSON named SET "${SCENE}" name "\"${bad}\"")
  file(WRITE "${WORK}/named.json" "${named}\n")
  execute_process(COMMAND "${RAYSPACE}" render "${WORK}/named.json" WORKING_DIRECTORY "${WORK}/sub"
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  math(EXPR CASES "${CASES} + 1")
  file(GLOB written "${WORK}/escaped*" "${WORK}/abs*" "${WORK}/sub/*" "${WORK}/.png")
  if(NOT rc EQUAL 2 OR NOT err MATCHES "named.json: the scene's \"name\" '[^\n]*' cannot name an output file: [^\n]*; give --out"
     OR written)
    set(FAILURES "${FAILURES}\n  [scene name '${bad}' as the default output] exit ${rc}, written: ${written}; stderr: ${err}")
    file(REMOVE ${written})
  endif()
endforeach()
# Two outputs that are one file, however spelled: ./x.png beside x.png before either exists, and a
# hard link to an existing image.
expect_error(NAME "--out x.png --stats ./x.png" NEEDLES "given as the output image and as the statistics file"
             ABSENT "${WORK}/x.png" ARGS render "${WORK}/good.json" --out x.png --stats ./x.png)
file(WRITE "${WORK}/old.png" "old")
file(CREATE_LINK "${WORK}/old.png" "${WORK}/hard.json")
expect_error(NAME "--stats a hard link to --out" NEEDLES "given as the output image and as the statistics file"
             ARGS render "${WORK}/good.json" --out "${WORK}/old.png" --stats "${WORK}/hard.json")
file(READ "${WORK}/old.png" old)
if(NOT old STREQUAL "old")
  set(FAILURES "${FAILURES}\n  [--stats a hard link to --out] the existing file was overwritten")
endif()
# An output directory is created, its parents are not.
expect_error(NAME "accuracy --out under a missing directory" NEEDLES "--out ${WORK}/nodir/acc: the directory ${WORK}/nodir does not exist"
             ABSENT "${WORK}/nodir" ARGS accuracy "${WORK}/good.json" --samples 100 --out "${WORK}/nodir/acc")

# --- An output that is an input ----------------------------------------------------------------
foreach(input good.json tri.obj)
  file(READ "${WORK}/${input}" before)
  set(scene good.json)
  if(input STREQUAL "tri.obj")
    set(scene mesh.json)
  endif()
  expect_error(NAME "--stats naming the input ${input}" NEEDLES "${input}: cannot write the statistics file: is also an input"
               ABSENT "${WORK}/x.png" ARGS render "${WORK}/${scene}" --out "${WORK}/x.png" --stats "${WORK}/${input}")
  file(READ "${WORK}/${input}" after)
  if(NOT before STREQUAL after)
    set(FAILURES "${FAILURES}\n  [--stats naming the input ${input}] the input was overwritten")
  endif()
endforeach()

# --- Writes that fail late --------------------------------------------------------------------
# A file size limit (ulimit -f, 512-byte blocks) fails the statistics file's writes after the frame; the
# image, written first, must go too. SIGXFSZ is ignored so that write() reports EFBIG. (Newlines, not
# semicolons, separate the shell's commands: a CMake list would split at them.)
set(limit sh -c "trap '' XFSZ\nulimit -f 4\nexec \"$0\" \"$@\"")
string(REPLACE "-f 4" "-f 1" limit_small "${limit}")  # the bench's JSON at 8x8 holds about 1 KB
expect_error(NAME "a write that fails late (file size limit)" NEEDLES "lim.json: cannot write the statistics file: File too large"
             ABSENT "${WORK}/lim.png" "${WORK}/lim.json" COMMAND ${limit}
             ARGS render "${WORK}/good.json" --size 32x32 --out "${WORK}/lim.png" --stats "${WORK}/lim.json")
set(full_stdout sh -c "exec \"$0\" \"$@\" > /dev/full")
expect_error(NAME "--stats - on a full standard output" NEEDLES "- (standard output): cannot write the statistics file"
             ABSENT "${WORK}/x.png" "${WORK}/-" COMMAND ${full_stdout}
             ARGS render "${WORK}/good.json" --out "${WORK}/x.png" --stats -)
expect_error(NAME "bench --json on a full device" NEEDLES "/dev/full: cannot write the JSON file"
             ARGS bench "${WORK}/good.json" --sizes 8x8 --configs embree --json /dev/full)
expect_error(NAME "bench --json, a write that fails late" NEEDLES "lim-bench.json: cannot write the JSON file: File too large"
             ABSENT "${WORK}/lim-bench.json" COMMAND ${limit_small}
             ARGS bench "${WORK}/good.json" --sizes 8x8 --configs embree,brute --repetitions 1 --json "${WORK}/lim-bench.json")
# The accuracy report's files are opened before the measurements.
file(MAKE_DIRECTORY "${WORK}/acc/good-accuracy.md")
expect_error(NAME "accuracy: a report file that is a directory" NEEDLES "good-accuracy.md: cannot write the accuracy table: is a directory"
             ABSENT "${WORK}/acc/good-accuracy.csv" "${WORK}/acc/good-accuracy.svg" "${WORK}/acc/good-accuracy.png"
             ARGS accuracy "${WORK}/good.json" --size 8x8 --samples 100 --out "${WORK}/acc")

# --- Positive cases ------------------------------------------------------------------------------
# --stats -: the statistics on standard output, alone.
math(EXPR CASES "${CASES} + 1")
execute_process(COMMAND "${RAYSPACE}" render "${WORK}/good.json" --size 24x24 --out "${WORK}/s.png" --stats -
                WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
string(JSON width ERROR_VARIABLE jerr GET "${out}" width)
if(NOT rc EQUAL 0 OR jerr OR NOT width EQUAL 24 OR EXISTS "${WORK}/-" OR NOT EXISTS "${WORK}/s.png")
  set(FAILURES "${FAILURES}\n  [--stats -] exit ${rc}, width '${width}' (${jerr}), a file named '-' or no image\n    stdout: ${out}\n    stderr: ${err}")
else()
  message(STATUS "ok: --stats -: the statistics on standard output")
endif()

# A scene file whose name is not UTF-8 (byte 0xFF): rendered with --stats, its name escaped as \xff.
math(EXPR CASES "${CASES} + 1")
execute_process(COMMAND sh -c "name=$(printf 'sc\\377ne.json'); cp good.json \"$name\" && exec \"$0\" render \"$name\" --out u.png --stats u.json"
                        "${RAYSPACE}"
                WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
set(json "")
if(EXISTS "${WORK}/u.json")
  file(READ "${WORK}/u.json" json)
endif()
string(JSON scene_file ERROR_VARIABLE jerr GET "${json}" scene_file)
if(NOT rc EQUAL 0 OR jerr OR NOT scene_file MATCHES "sc\\\\xffne\\.json$")
  set(FAILURES "${FAILURES}\n  [non-UTF-8 scene path] exit ${rc}, scene_file '${scene_file}' (${jerr})\n    stderr: ${err}")
else()
  message(STATUS "ok: non-UTF-8 scene path: scene_file ${scene_file}")
endif()

# SIGINT and SIGTERM while the frame renders: the process dies of the signal and leaves neither its
# outputs nor their temporary files. (A background job of sh ignores SIGINT: env restores it.)
foreach(sig INT TERM)
  math(EXPR CASES "${CASES} + 1")
  set(code 130)
  if(sig STREQUAL "TERM")
    set(code 143)
  endif()
  execute_process(COMMAND sh -c "env --default-signal=${sig} \"$0\" render good.json --size 1024x1024 --out sig.png --stats sig.json >/dev/null 2>&1 & pid=$!
i=0; until ls .sig.png.tmp-* >/dev/null 2>&1 || [ $i -ge 200 ]; do sleep 0.05; i=$((i+1)); done
kill -${sig} $pid; wait $pid; echo \"exit $?\"" "${RAYSPACE}"
                  WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
  file(GLOB left "${WORK}/sig.*" "${WORK}/.sig.*")
  if(NOT out MATCHES "exit ${code}" OR left)
    set(FAILURES "${FAILURES}\n  [SIG${sig}] ${out}${err}; left behind: ${left}")
    if(left)
      file(REMOVE ${left})
    endif()
  else()
    message(STATUS "ok: SIG${sig}: ${out}")
  endif()
endforeach()

cli_script_end(cli.outputs)
