# Sizes out of range are refused before anything is allocated, run as
#   cmake -DRAYSPACE=<exe> -DWORK=<scratch dir> -P cli_memory.cmake
# A frame whose estimated peak exceeds the machine's memory names --size, the estimate and the
# machine's memory; a scene whose instances would pass the triangle limit is refused by count
# before the copies are made; a frame that fits reports its estimate in --stats. diff (both backends
# and the differ's copies), bench (every size of every scene, before the first frame), accuracy and
# shadow-bench are refused the same way, and diff's --report carries its estimate.
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(failures "")
set(CAMERA [=["camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "fov_y_deg": 45}]=])
file(WRITE "${WORK}/box.json" "{${CAMERA}, \"image\": {\"width\": 16, \"height\": 16}, \"lights\": [{\"position\": [0, 4, 4]}], \"objects\": [{\"generator\": \"box\"}]}\n")
# 68 copies of a 3,998,792-triangle height field: 271.9 M triangles, beyond 2^28.
set(instances "{}")
foreach(i RANGE 1 67)
  string(APPEND instances ", {}")
endforeach()
file(WRITE "${WORK}/instances.json"
     "{${CAMERA}, \"image\": {\"width\": 16, \"height\": 16}, \"objects\": [{\"generator\": \"wavy\", \"params\": {\"resolution\": 1414}, \"instances\": [${instances}]}]}\n")

function(expect_refused name needles)
  execute_process(COMMAND "${RAYSPACE}" ${ARGN} WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
  string(REGEX MATCHALL "\n" lines "${err}")
  list(LENGTH lines n)
  if(NOT rc EQUAL 2 OR NOT n EQUAL 1)
    set(failures "${failures}\n[${name}] exit ${rc} (expected 2), ${n} stderr lines: ${err}" PARENT_SCOPE)
    return()
  endif()
  foreach(needle IN LISTS needles)
    string(FIND "${err}" "${needle}" at)
    if(at EQUAL -1)
      set(failures "${failures}\n[${name}] stderr does not name '${needle}': ${err}" PARENT_SCOPE)
    endif()
  endforeach()
  message(STATUS "ok: ${name}: ${err}")
endfunction()

expect_refused("16384x16384 frame" "--size 16384x16384;estimated;GB;machine" render box.json --size 16384x16384 --no-oracle --out big.png)
# The same size from the scene file: the message names the scene's image, not --size.
file(WRITE "${WORK}/big-image.json" "{${CAMERA}, \"image\": {\"width\": 16384, \"height\": 16384}, \"lights\": [{\"position\": [0, 4, 4]}], \"objects\": [{\"generator\": \"box\"}]}\n")
expect_refused("16384x16384 frame from the scene" "big-image.json: the scene's image 16384x16384;estimated;GB;machine"
               render big-image.json --no-oracle --out big.png)
expect_refused("instances past the triangle limit" "instances.json;objects[0].instances;2^28" render instances.json --no-oracle --out i.png)
if(VULKAN)
  expect_refused("16384x16384 diff" "--size 16384x16384;the diff;estimated;GB;machine" diff box.json --size 16384x16384 --report big-diff.json)
endif()
# The large size comes last: no frame of the small one may run before the refusal.
expect_refused("bench with a 16384x16384 size" "--sizes 16384x16384;box.json;estimated;GB;machine"
               bench box.json --sizes 16x16,16384x16384 --repetitions 1 --configs crsh --json big-bench.json --progress)
# accuracy and shadow-bench take --size as render does, and are refused the same way (before
# accuracy makes its output directory).
expect_refused("16384x16384 accuracy" "--size 16384x16384;the accuracy run;estimated;GB;machine"
               accuracy box.json --size 16384x16384 --out big-accuracy)
expect_refused("16384x16384 shadow bench" "--size 16384x16384;the shadow bench of box.json;estimated;GB;machine"
               shadow-bench box.json --size 16384x16384)
foreach(f big.png i.png big-diff.json big-bench.json big-accuracy)
  if(EXISTS "${WORK}/${f}")
    set(failures "${failures}\n${f} was left behind by a refused run")
  endif()
endforeach()

execute_process(COMMAND "${RAYSPACE}" render box.json --no-oracle --out ok.png --stats ok.json WORKING_DIRECTORY "${WORK}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  set(failures "${failures}\nthe 16x16 box frame failed: ${err}")
else()
  file(READ "${WORK}/ok.json" stats)
  string(JSON total ERROR_VARIABLE jerr GET "${stats}" memory_estimate total_bytes)
  if(jerr OR NOT total GREATER 0)
    set(failures "${failures}\nstats: memory_estimate.total_bytes is '${total}' (${jerr})")
  endif()
  string(FIND "${out}" "estimated before the frame" at)
  if(at EQUAL -1)
    set(failures "${failures}\nthe summary does not print the estimate:\n${out}")
  endif()
endif()

# Renders `name` (render's arguments after it, oracle off) and requires its estimate above its
# measured peak and above `floor` bytes.
function(expect_estimate_above name floor)
  execute_process(COMMAND "${RAYSPACE}" render ${ARGN} --no-oracle --out ${name}.png --stats ${name}-stats.json
                  WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
  if(NOT rc EQUAL 0)
    set(failures "${failures}\n${name}: exit ${rc}: ${err}" PARENT_SCOPE)
    return()
  endif()
  file(READ "${WORK}/${name}-stats.json" stats)
  string(JSON est ERROR_VARIABLE jerr GET "${stats}" memory_estimate total_bytes)
  string(JSON peak ERROR_VARIABLE jerr2 GET "${stats}" peak_rss_bytes)
  if(jerr OR jerr2 OR NOT est GREATER "${peak}" OR NOT est GREATER "${floor}")
    set(failures "${failures}\n${name}: estimate ${est} bytes, measured peak ${peak} (${jerr}${jerr2}), floor ${floor}: expected the estimate above both" PARENT_SCOPE)
  endif()
  message(STATUS "ok: ${name}: estimate ${est}, peak ${peak}")
endfunction()

# The estimate bounds the measured peak on every path that holds more than the fused emulator's
# frame: the pass-by-pass slot streams, and on Vulkan the device's copy (lavapipe's device memory is
# the host's) and the driver. Each must also be above the fused emulator's estimate.
set(paths "emu;passes")
if(VULKAN)
  list(APPEND paths vulkan fused vulkan passes)
endif()
set(i 0)
list(LENGTH paths n)
while(i LESS n)
  list(GET paths ${i} backend)
  math(EXPR j "${i} + 1")
  list(GET paths ${j} path)
  math(EXPR i "${i} + 2")
  expect_estimate_above("${backend}-${path}" "${total}" box.json --size 512x512 --backend ${backend} --path ${path})
endwhile()

# Many triangles and many objects: the estimate stays above the peak when the scene, not the frame,
# is what memory holds (a million triangles in one mesh at 16x16; ten thousand instances at 256x256,
# whose object tree holds its first round, every top node against every object, and its pair lists).
file(WRITE "${WORK}/many-triangles.json"
     "{${CAMERA}, \"image\": {\"width\": 16, \"height\": 16}, \"lights\": [{\"position\": [0, 4, 4]}], \"objects\": [{\"generator\": \"wavy\", \"params\": {\"resolution\": 775}}]}\n")
# Box i sits at (i % 22, i / 22 % 22, -(i / 484)) x 3: a row of 22 (and the last row's 12) written
# once with y and z left open, then filled per row (10,000 math() calls took CMake seconds).
set(row "")
set(last_row "")
foreach(x RANGE 0 63 3)
  string(APPEND row ", {\"translate\": [${x}, @Y@, -@Z@]}")
  if(x LESS 36)
    string(APPEND last_row ", {\"translate\": [${x}, @Y@, -@Z@]}")
  endif()
endforeach()
set(boxes "")
foreach(r RANGE 454)  # 454 rows of 22 and one of 12: 10,000 boxes
  math(EXPR y "${r} % 22 * 3")
  math(EXPR z "${r} / 22 * 3")
  if(r EQUAL 454)
    set(row "${last_row}")
  endif()
  string(REPLACE "@Y@" "${y}" line "${row}")
  string(REPLACE "@Z@" "${z}" line "${line}")
  string(APPEND boxes "${line}")
endforeach()
string(SUBSTRING "${boxes}" 2 -1 boxes)  # the leading ", "
file(WRITE "${WORK}/many-objects.json"
     "{\"camera\": {\"eye\": [33, 33, 88], \"target\": [33, 33, -33], \"fov_y_deg\": 45}, \"image\": {\"width\": 256, \"height\": 256}, "
     "\"lights\": [{\"position\": [33, 110, 66]}], \"materials\": {\"m\": {\"reflectivity\": 0.3}}, "
     "\"objects\": [{\"generator\": \"box\", \"material\": \"m\", \"instances\": [${boxes}]}], \"max_depth\": 1}\n")
foreach(name many-triangles many-objects)
  expect_estimate_above(${name} 0 ${name}.json)
endforeach()

# diff's estimate (two backends and the differ's copies) is in its report, above render's.
if(VULKAN)
  execute_process(COMMAND "${RAYSPACE}" diff box.json --report diff.json WORKING_DIRECTORY "${WORK}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    set(failures "${failures}\nthe 16x16 box diff failed: ${err}")
  else()
    file(READ "${WORK}/diff.json" report)
    string(JSON diff_total ERROR_VARIABLE jerr GET "${report}" memory_estimate total_bytes)
    if(jerr OR NOT diff_total GREATER "${total}")
      set(failures "${failures}\ndiff report: memory_estimate.total_bytes is '${diff_total}', render's '${total}' (${jerr})")
    endif()
  endif()
endif()
if(failures)
  message(FATAL_ERROR "${failures}")
endif()
