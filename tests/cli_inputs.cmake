# The CLI's contract for the files it reads, run as
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch dir> -DVULKAN=ON|OFF -P cli_inputs.cmake
# Every file rayspace reads (scene, mesh, MTL, a replay directory's files, a --kernel file) must be
# a regular file of bounded size: a directory, a FIFO, a device or an oversized file is exit code 2
# with one line naming the file and what it is, never a hang, a stream error or exhausted memory.
# FIFOs have no writer, so a read that blocks would hang: every case runs under a timeout.
cmake_minimum_required(VERSION 3.19)

include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
cli_script_begin(cli_inputs.cmake RAYSPACE SRC WORK)

find_program(MKFIFO mkfifo REQUIRED)
find_program(TRUNCATE truncate REQUIRED)
function(make_fifo path)
  file(REMOVE "${path}")
  execute_process(COMMAND "${MKFIFO}" "${path}" RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "cli_inputs.cmake: mkfifo ${path} failed")
  endif()
endfunction()
# A sparse file: its size is what fstat reports, without writing the bytes.
function(make_sparse path size)
  execute_process(COMMAND "${TRUNCATE}" -s "${size}" "${path}" RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "cli_inputs.cmake: truncate -s ${size} ${path} failed")
  endif()
endfunction()

set(CAMERA [=["camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 45}]=])
set(IMAGE [=["image": {"width": 16, "height": 16}]=])
set(LIGHTS [=["lights": [{"position": [0, 4, 4]}]]=])
# A scene of one mesh object named after its file.
function(mesh_scene name mesh)
  file(WRITE "${WORK}/${name}.json"
       "{${CAMERA}, ${IMAGE}, ${LIGHTS}, \"objects\": [{\"name\": \"m\", \"mesh\": \"${mesh}\"}]}\n")
endfunction()
# An OBJ triangle whose material comes from `mtllib <mtl>`.
function(obj_with_mtllib name mtl)
  file(WRITE "${WORK}/${name}.obj" "mtllib ${mtl}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n")
  mesh_scene(${name} ${name}.obj)
endfunction()
set(T 20)  # seconds: far more than any case needs, far less than ctest's limit
# expect_errors(<command> <case>...): each case three list items, its name, the input under WORK the
# command reads and the needles its one-line error must hold ('|' between them); `render` cases also
# write --out WORK/x.png, which must not be left behind.
macro(expect_errors command)
  set(_cases ${ARGN})
  list(LENGTH _cases _n)
  math(EXPR _last "${_n} - 1")
  foreach(_i RANGE 0 ${_last} 3)
    math(EXPR _j "${_i} + 1")
    math(EXPR _k "${_i} + 2")
    list(GET _cases ${_i} _name)
    list(GET _cases ${_j} _input)
    list(GET _cases ${_k} _needles)
    string(REPLACE "|" ";" _needles "${_needles}")
    set(_args ${command} "${WORK}/${_input}")
    if("${command}" STREQUAL "render")
      list(APPEND _args --out "${WORK}/x.png")
    endif()
    expect_error(NAME "${_name}" TIMEOUT ${T} NEEDLES ${_needles} ARGS ${_args})
  endforeach()
endmacro()

# --- Scene files --------------------------------------------------------------------------------
file(WRITE "${WORK}/good.json" "{${CAMERA}, ${IMAGE}, ${LIGHTS}, \"objects\": [{\"generator\": \"box\"}]}\n")
file(MAKE_DIRECTORY "${WORK}/dir.json")
make_fifo("${WORK}/fifo.json")
expect_errors(render
  "scene file is a directory" dir.json "dir.json|is a directory"
  "scene file is a FIFO" fifo.json "fifo.json|is a FIFO")
expect_error(NAME "scene file is a character device" TIMEOUT ${T}
             NEEDLES "/dev/null" "is a character device"
             ARGS render /dev/null --out "${WORK}/x.png")
expect_error(NAME "diff: scene file is a FIFO" TIMEOUT ${T}
             NEEDLES "fifo.json" "is a FIFO"
             ARGS diff "${WORK}/fifo.json")
expect_error(NAME "accuracy: scene file is a FIFO" TIMEOUT ${T}
             NEEDLES "fifo.json" "is a FIFO"
             ARGS accuracy "${WORK}/fifo.json" --out "${WORK}/acc")
expect_error(NAME "bench: scene file is a FIFO" TIMEOUT ${T}
             NEEDLES "fifo.json" "is a FIFO"
             ARGS bench "${WORK}/good.json" "${WORK}/fifo.json" --sizes 8x8)

# --- Meshes -------------------------------------------------------------------------------------
file(MAKE_DIRECTORY "${WORK}/dir.obj")
mesh_scene(mesh_dir dir.obj)
make_fifo("${WORK}/fifo.obj")
mesh_scene(mesh_fifo fifo.obj)
make_fifo("${WORK}/fifo.ply")
mesh_scene(ply_fifo fifo.ply)
file(CREATE_LINK /dev/zero "${WORK}/zero.ply" SYMBOLIC)
mesh_scene(ply_zero zero.ply)
make_sparse("${WORK}/huge.obj" 5G)
mesh_scene(mesh_huge huge.obj)
expect_errors(render
  "mesh is a directory" mesh_dir.json "mesh_dir.json|objects[0]|dir.obj|is a directory"
  "OBJ mesh is a FIFO" mesh_fifo.json "mesh_fifo.json|fifo.obj|is a FIFO"
  "PLY mesh is a FIFO" ply_fifo.json "ply_fifo.json|fifo.ply|is a FIFO"
  "PLY mesh is a link to /dev/zero" ply_zero.json "zero.ply|is a character device"
  "mesh larger than the bound (sparse 5 GiB)" mesh_huge.json "huge.obj|5368709120 bytes|4 GiB")

# --- MTL files ----------------------------------------------------------------------------------
make_fifo("${WORK}/fifo.mtl")
obj_with_mtllib(mtl_fifo fifo.mtl)
obj_with_mtllib(mtl_dev_zero /dev/zero)
file(CREATE_LINK /dev/zero "${WORK}/zero.mtl" SYMBOLIC)
obj_with_mtllib(mtl_zero_link zero.mtl)
file(MAKE_DIRECTORY "${WORK}/dir.mtl")
obj_with_mtllib(mtl_dir dir.mtl)
make_sparse("${WORK}/huge.mtl" 300M)
obj_with_mtllib(mtl_huge huge.mtl)
expect_errors(render
  "mtllib names a FIFO" mtl_fifo.json "fifo.mtl|mtllib of mtl_fifo.obj|is a FIFO"
  "mtllib names /dev/zero" mtl_dev_zero.json "/dev/zero|mtl_dev_zero.obj|is a character device"
  "mtllib names a link to /dev/zero" mtl_zero_link.json "zero.mtl|is a character device"
  "mtllib names a directory" mtl_dir.json "dir.mtl|is a directory"
  "mtllib larger than the bound (sparse 300 MiB)" mtl_huge.json "huge.mtl|314572800 bytes|256 MiB")

# --- Line ends: OBJ lines are checked as the parser splits them (CR, LF and CRLF alike) ------------
file(WRITE "${WORK}/cr_nan.obj" "v 0 0 0\rv 1 0 0\rv 0 1 0\rv nan 0 0\rf 1 2 3\r")
mesh_scene(cr_nan cr_nan.obj)
file(WRITE "${WORK}/cr_face.obj" "v 0 0 0\rv 1 0 0\r\nv 0 1 0\nf 1 2\rf 1 2 3\r")
mesh_scene(cr_face cr_face.obj)
expect_errors(render
  "CR-only OBJ with a NaN vertex" cr_nan.json "cr_nan.obj:4:|non-finite vertex coordinate 'nan'"
  "mixed line ends, a face of two vertices" cr_face.json "cr_face.obj:4:|face needs at least 3 vertices")

# --- MTL values: in range, or refused naming file, line and key ----------------------------------
file(WRITE "${WORK}/nan.mtl" "newmtl a\nKd nan 0.5 0.5\n")
obj_with_mtllib(mtl_nan nan.mtl)
file(WRITE "${WORK}/neg.mtl" "newmtl a\nKd 0.5 0.5 0.5\nKs -2 0 0\n")
obj_with_mtllib(mtl_neg neg.mtl)
file(WRITE "${WORK}/ns.mtl" "newmtl a\rKd 0.5 0.5 0.5\rNs 1e9\r")
obj_with_mtllib(mtl_ns ns.mtl)
expect_errors(render
  "MTL Kd NaN" mtl_nan.json "nan.mtl:2: Kd: 'nan' is not finite"
  "MTL Ks negative" mtl_neg.json "neg.mtl:3: Ks: -2 out of range"
  "MTL Ns far out of range (CR-only file)" mtl_ns.json "ns.mtl:3: Ns: 1e9 out of range [0, 4096]")

# --- gzip-compressed meshes, made here: the same frame as the plain mesh, or exit 2 naming the file --
file(WRITE "${WORK}/quad.obj" "o quad\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n")
file(ARCHIVE_CREATE OUTPUT "${WORK}/quad.obj.gz" PATHS "${WORK}/quad.obj" FORMAT raw COMPRESSION GZip)
mesh_scene(quad_plain quad.obj)
mesh_scene(quad_gz quad.obj.gz)
set(digests "")
foreach(scene quad_plain quad_gz)
  math(EXPR CASES "${CASES} + 1")
  execute_process(COMMAND "${RAYSPACE}" render "${WORK}/${scene}.json" --out "${WORK}/${scene}.png"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
  string(REGEX MATCH "digest +([0-9a-f]+)" found "${out}")
  if(NOT rc EQUAL 0 OR NOT found)
    set(FAILURES "${FAILURES}\n  [${scene}] exit code '${rc}', no digest\n    ${out}${err}")
  else()
    list(APPEND digests "${CMAKE_MATCH_1}")
  endif()
endforeach()
list(LENGTH digests n)
list(REMOVE_DUPLICATES digests)
list(LENGTH digests distinct)
if(n EQUAL 2 AND distinct EQUAL 1)
  message(STATUS "ok: quad.obj.gz renders the frame of quad.obj (digest ${digests})")
elseif(n EQUAL 2)
  set(FAILURES "${FAILURES}\n  [quad.obj.gz] digests differ from quad.obj: ${digests}")
endif()
execute_process(COMMAND head -c 20 "${WORK}/quad.obj.gz" OUTPUT_FILE "${WORK}/cut.obj.gz")
mesh_scene(gz_cut cut.obj.gz)
file(WRITE "${WORK}/text.obj.gz" "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
mesh_scene(gz_text text.obj.gz)
expect_errors(render
  "truncated .obj.gz" gz_cut.json "cut.obj.gz|truncated gzip data"
  ".obj.gz that is not gzip" gz_text.json "text.obj.gz|not valid gzip data")

# --- Replay directories -------------------------------------------------------------------------
file(MAKE_DIRECTORY "${WORK}/replay_fifo")
make_fifo("${WORK}/replay_fifo/pass.json")
file(MAKE_DIRECTORY "${WORK}/replay_dir/pass.json")
file(MAKE_DIRECTORY "${WORK}/replay_bin")
file(WRITE "${WORK}/replay_bin/pass.json" "{\"method\": \"trim\", \"buffers\": {\"rays\": {\"type\": \"u32\", \"count\": 1}}}\n")
make_fifo("${WORK}/replay_bin/rays.bin")
file(WRITE "${WORK}/replay_file" "not a directory\n")
expect_errors(replay
  "replay: pass.json is a FIFO" replay_fifo "replay_fifo/pass.json|is a FIFO"
  "replay: pass.json is a directory" replay_dir "replay_dir/pass.json|is a directory"
  "replay: a buffer file is a FIFO" replay_bin "replay_bin/rays.bin|is a FIFO"
  "replay: the directory is a file" replay_file "replay_file|not a directory")

# --- Files only the Vulkan side reads: a saved call's recorded comparison, --kernel files ------------
if(VULKAN)
  execute_process(COMMAND "${RAYSPACE}" diff "${WORK}/good.json" --size 8x8 --save-inputs "${WORK}/saved"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
  file(GLOB trim_call LIST_DIRECTORIES true "${WORK}/saved/*-trim.shadow.b0")
  if(NOT rc EQUAL 0 OR NOT trim_call)
    set(FAILURES "${FAILURES}\n  [diff --save-inputs] exit code '${rc}', no trim call saved\n    ${out}${err}")
  else()
    make_fifo("${trim_call}/comparison.json")
    expect_error(NAME "replay: comparison.json is a FIFO" TIMEOUT ${T}
                 NEEDLES "comparison.json" "is a FIFO"
                 ARGS replay "${trim_call}")
  endif()
  make_fifo("${WORK}/fifo.comp")
  file(MAKE_DIRECTORY "${WORK}/dir.spv")
  expect_error(NAME "--kernel names a FIFO" TIMEOUT ${T}
               NEEDLES "--kernel" "fifo.comp" "is a FIFO"
               ARGS render "${WORK}/good.json" --backend vulkan --kernel "trim=${WORK}/fifo.comp" --out "${WORK}/x.png")
  expect_error(NAME "--kernel names a directory" TIMEOUT ${T}
               NEEDLES "--kernel" "dir.spv" "is a directory"
               ARGS diff "${WORK}/good.json" --kernel "trim=${WORK}/dir.spv")
endif()

cli_script_end(cli.inputs)
