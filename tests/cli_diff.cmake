# `rayspace diff`: the Vulkan kernels equal the emulator on the bundled scenes, and every planted
# fault makes the diff fail with its own pass reported first. Each case is its own ctest,
# cli.diff.<case>, so a failure names what it checks:
#   <scene>.<algo>[.<variant>]       the frame is equal on both backends (exit 0)
#   fault.[<algo>.]<pass>:<fault>   the planted fault is caught, with <pass> the first divergent pass (exit 4)
#   faults.<group>                  each planted fault of a list likewise, a frame each on one device
#   replay.<what>                   saved inputs replay to the recorded comparison
# tests/CMakeLists.txt includes this file with CASE unset to collect the case names; each test runs
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DDATA=<data root> -DWORK=<scratch> -DCASE=<case> -P cli_diff.cmake
# A case whose data is missing prints "cli.diff: skipped" (the tests' SKIP_REGULAR_EXPRESSION).
set(cli_diff_cases "")       # every case, in order
set(cli_diff_after_save "")  # cases that read the inputs replay.save writes (a ctest fixture)
set(matched FALSE)
set(skipped FALSE)
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
cli_case_begin()

# Records `name`; sets `result` when `name` is the case to run (never in listing mode).
macro(case_selected name result)
  set(${result} FALSE)
  list(APPEND cli_diff_cases "${name}")
  if(DEFINED CASE AND "${CASE}" STREQUAL "${name}")
    set(matched TRUE)
    set(${result} TRUE)
  endif()
endmacro()

# The start of a case function: records `name` and returns from the function unless it is the case
# to run. A macro, so that its return() leaves the calling function.
macro(begin_case name)
  case_selected("${name}" run)
  set(cli_diff_cases "${cli_diff_cases}" PARENT_SCOPE)
  if(NOT run)
    return()
  endif()
  set(matched TRUE PARENT_SCOPE)
endmacro()

# A scene by name: a bundled scene, or one of the variants below written into the case's folder.
function(scene_path scene out)
  set(path "${SRC}/scenes/${scene}.json")
  file(READ "${SRC}/scenes/cornell-mirrors.json" cornell)
  if(scene STREQUAL "area-shapes")
    # One light of each area shape beside a point light: every branch of the sampler
    # (rayspace/kernel_functions.h, light_sample.glsl) and the slot layout of several lights.
    file(READ "${SRC}/scenes/cornell-soft.json" soft)
    string(JSON soft SET "${soft}" lights 1 "{\"shape\": \"disk\", \"radius\": 40, \"normal\": [0.3, -1, 0.2], \"samples\": 6, \"position\": [150, 500, 300], \"intensity\": 0.5, \"attenuation\": [1, 0, 1e-6]}")
    string(JSON soft SET "${soft}" lights 2 "{\"shape\": \"sphere\", \"radius\": 25, \"samples\": 5, \"position\": [420, 420, 200], \"intensity\": 0.5, \"attenuation\": [1, 0, 1e-6]}")
    string(JSON soft SET "${soft}" lights 3 "{\"position\": [300, 300, 100], \"intensity\": 0.2, \"attenuation\": [1, 0, 1e-6]}")
    string(JSON soft SET "${soft}" max_depth 2)
    set(path "${case_work}/area-shapes.json")
    file(WRITE "${path}" "${soft}")
  elseif(scene STREQUAL "glass")
    # A transparent object brings the refraction kernels in.
    string(JSON glass SET "${cornell}" materials clay transparency 0.5)
    string(JSON glass SET "${glass}" materials clay reflectivity 0.2)
    string(JSON glass SET "${glass}" materials clay ior 1.5)
    set(path "${case_work}/glass-scene.json")
    file(WRITE "${path}" "${glass}")
  elseif(scene STREQUAL "studs")
    # 300 small boxes as separate objects make CRSH's object mask (top nodes x objects) outgrow a
    # 256 KiB binding at 128x128, so the mask is computed in parts and read by rows.
    set(studs "[]")
    foreach(i RANGE 299)
      math(EXPR x "40 + (${i} % 20) * 25")
      math(EXPR y "20 + (${i} / 20) * 8")
      string(JSON studs SET "${studs}" ${i} "{\"translate\": [${x}, ${y}, 300]}")
    endforeach()
    string(JSON studs_scene SET "${cornell}" objects 2 "{\"name\": \"studs\", \"generator\": \"box\", \"params\": {\"size\": 6}, \"material\": \"clay\", \"instances\": ${studs}}")
    set(path "${case_work}/studs-scene.json")
    file(WRITE "${path}" "${studs_scene}")
  endif()
  set(${out} "${path}" PARENT_SCOPE)
endfunction()

# diff_case(NAME SCENE SIZE INJECT EXPECT_RC EXPECT_FIRST [diff options...]): runs `rayspace diff`
# when NAME is the case; the report is the case folder's report.json.
function(diff_case name scene size inject expect_rc expect_first)
  begin_case("${name}")
  set(extra ${ARGN})
  if(inject)
    list(APPEND extra --inject ${inject})
  endif()
  # A divergence's impact (two more frames, one per backend alone) is impact_case's to check; here
  # the verdict is the first divergent pass.
  if(expect_rc EQUAL 4)
    list(APPEND extra --no-impact)
  endif()
  scene_path("${scene}" path)
  execute_process(COMMAND "${RAYSPACE}" diff "${path}" --data "${DATA}" --size ${size}
                          --report "${case_work}/report.json" ${extra}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(case_out "${out}" PARENT_SCOPE)  # for checks after the call
  if(NOT rc EQUAL expect_rc)
    set(FAILURES "${FAILURES}\n${name}: exit ${rc}, expected ${expect_rc}: ${out}${err}" PARENT_SCOPE)
    return()
  endif()
  file(READ "${case_work}/report.json" j)
  string(JSON first GET "${j}" first_divergent_pass)  # JSON null reads as ""
  string(JSON equal GET "${j}" equal)
  if(expect_rc EQUAL 0 AND NOT equal)
    set(FAILURES "${FAILURES}\n${name}: report says not equal" PARENT_SCOPE)
  endif()
  string(JSON within GET "${j}" calls_within_spec)
  if(extra MATCHES "--compare;relaxed" AND expect_rc EQUAL 0 AND inject)
    # A device-like fault under the relaxed comparison: seen, and accepted as within the spec.
    if(within EQUAL 0 OR NOT out MATCHES "planted fault ${inject}: seen, and every difference is within the spec's precision")
      set(FAILURES "${FAILURES}\n${name}: the fault was not seen and accepted as within the spec: ${out}" PARENT_SCOPE)
    endif()
  elseif(expect_rc EQUAL 0 AND inject AND NOT out MATCHES "planted fault ${inject}: not seen, the device executed it benignly")
    set(FAILURES "${FAILURES}\n${name}: an unseen planted fault is not reported as benign: ${out}" PARENT_SCOPE)
  endif()
  if(NOT "${first}" STREQUAL "${expect_first}")
    set(FAILURES "${FAILURES}\n${name}: first divergent pass '${first}', expected '${expect_first}'" PARENT_SCOPE)
  endif()
  # The impact of a divergence is measured only when there is one.
  string(JSON impact_type TYPE "${j}" impact)
  if(expect_rc EQUAL 0 AND NOT impact_type STREQUAL "NULL")
    set(FAILURES "${FAILURES}\n${name}: an equal diff reports an impact (${impact_type})" PARENT_SCOPE)
  endif()
  # A divergence is a verdict: on stderr, where errors go, not only in the summary.
  if(expect_rc EQUAL 4 AND NOT err MATCHES "rayspace diff: first divergent pass: ${expect_first}\n")
    set(FAILURES "${FAILURES}\n${name}: stderr does not give the first divergent pass: ${err}" PARENT_SCOPE)
  endif()
endfunction()

# impact_case(NAME SCENE SIZE INJECT EXPECT [diff options...]): the planted fault diverges (exit 4)
# and the frame runs on each backend alone. EXPECT "changes": rays' final hits and pixels change, and
# the exact oracle says the emulator is right (vulkan on none); "invisible": no hit and no pixel
# changes in this frame, which is not called benign: the summary names what differed instead.
function(impact_case name scene size inject expect)
  begin_case("${name}")
  scene_path("${scene}" path)
  execute_process(COMMAND "${RAYSPACE}" diff "${path}" --data "${DATA}" --size ${size} --inject ${inject}
                          --report "${case_work}/report.json" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 4)
    set(FAILURES "${FAILURES}\n${name}: exit ${rc}, expected 4: ${out}${err}" PARENT_SCOPE)
    return()
  endif()
  file(READ "${case_work}/report.json" j)
  foreach(key measured no_visible_change rays rays_changed pixels_changed judged)
    string(JSON ${key} ERROR_VARIABLE jerr GET "${j}" impact ${key})
  endforeach()
  string(JSON emu_right ERROR_VARIABLE jerr GET "${j}" impact verdicts emulator)
  string(JSON vk_right ERROR_VARIABLE jerr GET "${j}" impact verdicts vulkan)
  # The actual side is named by its backend in the summary and the report (vulkan, or sim).
  set(actual vulkan)
  if(ARGN MATCHES "emu,sim")
    set(actual sim)
  endif()
  string(JSON actual_name ERROR_VARIABLE jerr GET "${j}" impact actual)
  if(NOT actual_name STREQUAL actual)
    set(FAILURES "${FAILURES}\n${name}: the report names the actual side '${actual_name}', expected '${actual}'" PARENT_SCOPE)
  endif()
  set(facts "measured ${measured}, no visible change ${no_visible_change}, ${rays_changed} of ${rays} rays, ${pixels_changed} pixels, emulator right on ${emu_right}, vulkan on ${vk_right} (${jerr})")
  if(expect STREQUAL "changes")
    string(JSON first_verdict ERROR_VARIABLE jerr GET "${j}" impact changed_rays 0 verdict)
    if(NOT measured OR no_visible_change OR NOT rays_changed GREATER 0 OR NOT pixels_changed GREATER 0 OR NOT emu_right GREATER 0
       OR NOT vk_right EQUAL 0 OR first_verdict STREQUAL "vulkan"
       OR NOT err MATCHES "impact: [0-9]+ of [0-9]+ rays change their final hit \\(emulator right on [1-9][0-9]*, ${actual} on 0")
      set(FAILURES "${FAILURES}\n${name}: expected changed hits and pixels, the emulator right: ${facts}\n${err}" PARENT_SCOPE)
    endif()
  elseif(NOT measured OR NOT no_visible_change OR NOT rays_changed EQUAL 0 OR NOT pixels_changed EQUAL 0 OR NOT rays GREATER 0
         OR NOT err MATCHES "impact: no ray's final hit and no pixel changes in this frame [^\n]*; not proven benign: ([a-z.]+/[a-z_]+|candidate pairs): "
         OR err MATCHES "impact: benign")
    set(FAILURES "${FAILURES}\n${name}: expected no visible change, not called benign, what differed named: ${facts}\n${err}" PARENT_SCOPE)
  endif()
  # A traversal fault: the candidate pairs one side lost or added, counted against the reference's,
  # and a lost pair not called harmless.
  if(inject MATCHES "^traverse" AND NOT err MATCHES "\n    pairs: [0-9]+ of the reference's [1-9][0-9]* candidate pairs lost, [0-9]+ added; first (lost|added): \\(node [0-9]+, triangle [0-9]+\\)")
    set(FAILURES "${FAILURES}\n${name}: the first divergence does not count the candidate pairs lost and added:\n${err}" PARENT_SCOPE)
  endif()
  # ... and whether what was lost could hit: each final ray-triangle test the Vulkan side's frame lost,
  # run again. A hidden hit (office) is named; a loss whose tests all miss (cornell-mirrors) is said to
  # change no hit.
  if(inject MATCHES "^traverse")
    string(JSON lost ERROR_VARIABLE jerr GET "${j}" impact final_tests lost)
    string(JSON meeting ERROR_VARIABLE jerr GET "${j}" impact final_tests lost_meeting_triangle)
    if(expect STREQUAL "changes")
      set(judged "[1-9][0-9]* lost tests meet their triangle \\(first: [a-z]+\\.b[0-9]+ ray [0-9]+, triangle [0-9]+\\): hits the loss can take away")
      set(json_ok "${meeting}" GREATER 0)
    else()
      set(judged "no lost test meets its triangle, so the loss changes no hit in this frame")
      set(json_ok "${meeting}" EQUAL 0)
    endif()
    if(NOT lost GREATER 0 OR NOT (${json_ok}) OR NOT err MATCHES "\n    final ray-triangle tests: the ${actual} side's frame lost [1-9][0-9]* of the emulator's and added [0-9]+; ${judged}")
      set(FAILURES "${FAILURES}\n${name}: the lost final tests are not judged as expected (lost ${lost}, meeting ${meeting}):\n${err}" PARENT_SCOPE)
    endif()
  endif()
endfunction()

# run_each(NAME SCENE SIZE FAULTS EXPECT_RC [diff options...]): diff --inject-each over the list FAULTS
# (--no-impact), a frame each on one device (the device and its pipelines made once); sets `out`, `err`
# and `j` (the report) in the caller, or returns from it after recording an unexpected exit.
macro(run_each name scene size faults expect_rc)
  scene_path("${scene}" path)
  string(REPLACE ";" "," each "${faults}")
  execute_process(COMMAND "${RAYSPACE}" diff "${path}" --data "${DATA}" --size ${size} --inject-each "${each}" --no-impact
                          --report "${case_work}/report.json" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL ${expect_rc})
    set(FAILURES "${FAILURES}\n${name}: exit ${rc}, expected ${expect_rc}: ${out}${err}" PARENT_SCOPE)
    return()
  endif()
  file(READ "${case_work}/report.json" j)
  list(LENGTH faults count)
  string(JSON reported LENGTH "${j}" faults)
  if(NOT reported EQUAL count)
    set(FAILURES "${FAILURES}\n${name}: ${reported} frames reported, expected ${count}" PARENT_SCOPE)
    return()
  endif()
endmacro()

# faults_case(NAME SCENE SIZE FAULTS [diff options...]): each planted fault of the list FAULTS must
# diverge with its own pass first (PASS:N and PASS:N@emu -> PASS). A failure names each fault missed.
function(faults_case name scene size faults)
  begin_case("${name}")
  run_each("${name}" "${scene}" ${size} "${faults}" 4 ${ARGN})
  string(REGEX MATCHALL "rayspace diff: first divergent pass: [^\n]+" verdicts "${err}")
  list(LENGTH verdicts said)
  if(NOT said EQUAL count)
    set(FAILURES "${FAILURES}\n${name}: ${said} divergences said on stderr, expected ${count}" PARENT_SCOPE)
  endif()
  # Under --compare relaxed each divergence is the model's verdict (elements beyond the spec), not a
  # pass without a model compared word for word.
  string(REGEX MATCHALL "relaxed model: [0-9]+ element\\(s\\) within the spec's precision, [1-9][0-9]* beyond" judged "${err}")
  list(LENGTH judged judged)
  if(ARGN MATCHES "--compare;relaxed" AND NOT judged EQUAL count)
    set(FAILURES "${FAILURES}\n${name}: ${judged} divergences judged beyond the spec by a relaxed model, expected ${count}" PARENT_SCOPE)
  endif()
  set(i 0)
  foreach(f IN LISTS faults)
    string(REGEX REPLACE "[:@].*" "" pass "${f}")
    string(JSON inject GET "${j}" faults ${i} inject)
    string(JSON first GET "${j}" faults ${i} first_divergent_pass)  # JSON null reads as ""
    string(JSON measured ERROR_VARIABLE no_impact GET "${j}" faults ${i} impact measured)  # null when equal
    if(NOT inject STREQUAL f OR NOT first STREQUAL pass OR measured)
      set(FAILURES "${FAILURES}\n${name}: frame ${i} (${inject}, expected ${f}): first divergent pass '${first}', expected '${pass}'" PARENT_SCOPE)
    endif()
    math(EXPR i "${i} + 1")
  endforeach()
endfunction()

# within_spec_case(NAME SCENE SIZE FAULTS [diff options...]): each device-like fault of the list, under
# --compare relaxed, is seen and accepted as within the spec (exit 0, the frame's calls_within_spec
# above 0, the summary saying so for each fault).
function(within_spec_case name scene size faults)
  begin_case("${name}")
  run_each("${name}" "${scene}" ${size} "${faults}" 0 --compare relaxed ${ARGN})
  set(i 0)
  foreach(f IN LISTS faults)
    string(JSON inject GET "${j}" faults ${i} inject)
    string(JSON within GET "${j}" faults ${i} calls_within_spec)
    string(JSON equal GET "${j}" faults ${i} equal)
    string(FIND "${out}" "planted fault ${f}: seen, and every difference is within the spec's precision" said)
    if(NOT inject STREQUAL f OR within EQUAL 0 OR NOT equal OR said EQUAL -1)
      set(FAILURES "${FAILURES}\n${name}: frame ${i} (${inject}, expected ${f}): ${within} calls within the spec, equal ${equal}, said ${said}" PARENT_SCOPE)
    endif()
    math(EXPR i "${i} + 1")
  endforeach()
endfunction()

# checker_case(NAME SCENE SIZE INJECT PASS [diff options...]): a fault planted in an emulated kernel
# (INJECT ends in @emu) must stop the diff with exit 6, before any comparison of PASS, with the
# workgroup checker's reports naming PASS, a shared word (or, for a divergent barrier, listed
# first, the invocations that reached it and did not) and the invocations.
function(checker_case name scene size inject pass)
  begin_case("${name}")
  scene_path("${scene}" path)
  execute_process(COMMAND "${RAYSPACE}" diff "${path}" --data "${DATA}" --size ${size} --inject ${inject}
                          --report "${case_work}/report.json" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 6 OR NOT err MATCHES "workgroup checker: [0-9]+ report\\(s\\) in ${pass}\\.[A-Za-z]+ \\(pass ${pass}\\)")
    set(FAILURES "${FAILURES}\n${name}: exit ${rc}, expected 6 and the checker naming ${pass}: ${out}${err}" PARENT_SCOPE)
    return()
  endif()
  file(READ "${case_work}/report.json" j)
  string(JSON checked GET "${j}" workgroup_checker pass)
  string(JSON word GET "${j}" workgroup_checker reports 0 word)
  string(JSON inv GET "${j}" workgroup_checker reports 0 invocations 0)
  string(JSON array GET "${j}" workgroup_checker reports 0 array)
  string(JSON kind GET "${j}" workgroup_checker reports 0 kind)
  if(kind STREQUAL "divergent barrier")  # names the two invocations, no word
    set(array "wg_tile")
  endif()
  string(JSON compared LENGTH "${j}" calls)
  foreach(k RANGE ${compared})
    if(k LESS compared)
      string(JSON p GET "${j}" calls ${k} pass)
      if(p STREQUAL pass)
        set(FAILURES "${FAILURES}\n${name}: ${pass} was compared before the checker stopped it" PARENT_SCOPE)
      endif()
    endif()
  endforeach()
  if(NOT checked STREQUAL pass OR NOT array STREQUAL "wg_tile" OR inv GREATER 1023 OR word STREQUAL "")
    set(FAILURES "${FAILURES}\n${name}: checker report names pass '${checked}', array '${array}', word '${word}', invocation '${inv}'" PARENT_SCOPE)
  endif()
endfunction()

# replay_check(DIR EXPECT_RC EXPECT_TEXT [replay options...])
function(replay_check dir expect_rc expect_text)
  execute_process(COMMAND "${RAYSPACE}" replay "${dir}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL expect_rc OR NOT "${out}${err}" MATCHES "${expect_text}")
    set(FAILURES "${FAILURES}\nreplay ${CASE}: exit ${rc} (expected ${expect_rc}), output: ${out}${err}" PARENT_SCOPE)
  endif()
endfunction()

# The start of a case that reads a call replay.save wrote: records `name` (after the save), returns
# unless it is the case to run, and sets `dir` to the saved call matching `pattern` (or fails).
macro(begin_saved_case name pattern)
  set(cli_diff_after_save ${cli_diff_after_save} ${name} PARENT_SCOPE)
  begin_case("${name}")
  file(GLOB dir "${WORK}/saved/${pattern}")
  if(NOT dir)
    set(FAILURES "${FAILURES}\n${name}: no saved ${pattern} call under ${WORK}/saved" PARENT_SCOPE)
    return()
  endif()
endmacro()

# replay_saved(NAME PATTERN EXPECT_RC EXPECT_TEXT [replay options...]): replays the call replay.save
# wrote under WORK/saved whose folder matches PATTERN.
function(replay_saved name pattern expect_rc expect_text)
  begin_saved_case("${name}" "${pattern}")
  replay_check("${dir}" ${expect_rc} "${expect_text}" ${ARGN})
  set(FAILURES "${FAILURES}" PARENT_SCOPE)
endfunction()

diff_case(cornell.crsh cornell-mirrors 512x512 "" 0 "")
diff_case(cornell.rah cornell-mirrors 128x128 "" 0 "" --algo rah)
diff_case(cornell.rah-quadtree cornell-mirrors 96x96 "" 0 "" --algo rah-quadtree)
diff_case(cornell.crsh.scan cornell-mirrors 128x128 "" 0 "" --reduction scan)
diff_case(cornell.brute cornell-mirrors 96x96 "" 0 "" --algo brute)
diff_case(office.crsh office 128x128 "" 0 "")
diff_case(office.rah office 96x96 "" 0 "" --algo rah)
diff_case(glass.crsh glass 128x128 "" 0 "")
# Workgroup sizes and dispatch splitting must not change a bit (order-preserving compaction,
# order-independent reductions). 64x64: four workgroups of 1,024 per pixel pass, more of the others.
foreach(ls 1 7 12 20 32 256 1024)
  diff_case(cornell.crsh.local-size-${ls} cornell-mirrors 64x64 "" 0 "" --local-size ${ls})
endforeach()
# Every bundled scene at local sizes 32, 64 and 256 and every emulator schedule (the emulated
# workgroup kernels with the checker on): each pair of sizes and orders must give the same bits.
foreach(scene cornell-mirrors office sponza)
  foreach(ls 32 64 256)
    foreach(schedule forward reverse random:7)
      set(name ${scene}.schedule.${ls}.${schedule})
      if("${CASE}" STREQUAL "${name}" AND scene STREQUAL "sponza" AND NOT EXISTS "${DATA}/sponza_dabrovic/sponza.obj")
        case_selected(${name} run)
        set(skipped TRUE)
        message("cli.diff: skipped, no sponza_dabrovic/sponza.obj under ${DATA}")
      else()
        diff_case(${name} ${scene} 64x64 "" 0 "" --local-size ${ls} --schedule ${schedule})
      endif()
    endforeach()
  endforeach()
endforeach()
# Components smaller than a workgroup and not a multiple of it (one workgroup per component).
diff_case(cornell.crsh.component-7 cornell-mirrors 64x64 "" 0 "" --component-size 7 --local-size 32)
# Bindings far below maxStorageBufferRange: parts, pages, pair-stream splits; launches in rows.
diff_case(cornell.crsh.paged cornell-mirrors 96x96 "" 0 "" --split-bytes 163840)
if("${CASE}" STREQUAL "cornell.crsh.paged" AND NOT FAILURES)
  file(READ "${case_work}/report.json" j)
  string(JSON splits GET "${j}" split_dispatches)
  string(JSON paged GET "${j}" paged_arrays)
  if(splits LESS 100 OR paged LESS 10)
    set(FAILURES "${FAILURES}\ncornell.crsh.paged: ${splits} split dispatches, ${paged} paged arrays; the paths did not run")
  endif()
endif()
diff_case(cornell.crsh.scan.paged cornell-mirrors 96x96 "" 0 "" --split-bytes 163840 --reduction scan)
diff_case(cornell.crsh.split cornell-mirrors 48x40 "" 0 "" --split-bytes 65536)
# A device whose device-local memory the host cannot map (a discrete GPU without resizable BAR):
# every storage buffer is staged through copies on the queue, under the validation layer.
diff_case(cornell.crsh.staged cornell-mirrors 64x64 "" 0 "" --device-lacks mappableDeviceLocal)
diff_case(cornell.crsh.staged.paged cornell-mirrors 96x96 "" 0 "" --device-lacks mappableDeviceLocal --split-bytes 163840)
diff_case(cornell.crsh.rows cornell-mirrors 96x96 "" 0 "" --max-groups 2)
# A pair capacity far below the frame's pairs splits triangle batches and node groups on both backends.
diff_case(cornell.crsh.pair-capacity cornell-mirrors 96x80 "" 0 "" --pair-capacity 3000 --component-size 16)
# Faults that only the split, paged or folded paths can show; each fails its own pass first.
diff_case(fault.trim:2 cornell-mirrors 96x96 trim:2 4 trim --split-bytes 163840)
diff_case(fault.intersect:2 cornell-mirrors 96x96 intersect:2 4 intersect --split-bytes 163840)
diff_case(fault.hash:2 cornell-mirrors 96x96 hash:2 4 hash --max-groups 2)
diff_case(studs.crsh.paged studs 128x128 "" 0 "" --split-bytes 262144)
# At depth 1 the mask (2,048 top nodes x 307 objects) outgrows even four such bindings: the top
# level binds only the mask rows of each dispatch's top nodes.
diff_case(studs.crsh.depth-1 studs 128x128 "" 0 "" --split-bytes 262144 --depth 1)
diff_case(fault.traverse:2 studs 128x128 traverse:2 4 traverse --split-bytes 262144)
foreach(algo crsh rah)
  set(args "")
  if(algo STREQUAL "rah")
    set(args --algo rah)
  endif()
  if("${CASE}" STREQUAL "sponza.${algo}" AND NOT EXISTS "${DATA}/sponza_dabrovic/sponza.obj")
    case_selected(sponza.${algo} run)
    set(skipped TRUE)
    message("cli.diff: skipped, no sponza_dabrovic/sponza.obj under ${DATA}")
  else()
    diff_case(sponza.${algo} sponza 128x128 "" 0 "" ${args})
  endif()
endforeach()
faults_case(faults.first cornell-mirrors 64x64 "raster:1;surfaces:1;raygen.shadow:1;raygen.shadow:2;trim:1;hash:1;compress:1;sort:1;decompress:1;build:1;traverse:1;reduce:1;intersect:1;shade:1;raygen.reflection:1;surfaces.hits:1;resolve:1")
# Every pass's own faults beyond its first: a wrong operand, an off-by-one bound or index, a lost tail,
# a swapped index; each fires on every frame and is caught in its own pass.
# Among them, outputs the host checks (surfaces:4 a material id, build:4 a leaf's ray count): the diff
# compares them first; and slots left unwritten (traverse:4): they read back as the buffers' poison,
# never as a right value.
faults_case(faults.more cornell-mirrors 64x64 "raster:3;surfaces:2;surfaces:3;surfaces.hits:2;surfaces.hits:3;raygen.shadow:3;raygen.reflection:2;raygen.reflection:3;trim:3;hash:3;compress:2;compress:3;sort:2;sort:3;decompress:2;decompress:3;build:2;build:3;traverse:3;reduce:3;intersect:3;shade:2;shade:3;resolve:2;resolve:3;surfaces:4;build:4;traverse:4")
# Area lights (docs/area-lights.md): each shape's samples equal on both sides, the relaxed device
# model bounding a sample a device's square root moves, and the sampler's faults, which a scene of
# point lights cannot see, caught in their passes.
diff_case(area.shapes area-shapes 48x48 "" 0 "")
diff_case(area.shapes.relaxed area-shapes 48x48 raygen.shadow:approx-sqrt 0 "" --compare relaxed)
faults_case(faults.area area-shapes 32x32 "raygen.shadow:4;raygen.shadow:5;raygen.shadow:6;shade:4;shade:5")
# Refraction rays need a transparent object.
faults_case(faults.refraction glass 96x96 "raygen.refraction:1;raygen.refraction:2;raygen.refraction:3")
# The raster's faults, classified: a half-pixel shift (what a device snapping differently does)
# changes edge pixels only; the depth scale, interior ones.
diff_case(fault.raster:2 cornell-mirrors 64x64 raster:2 4 raster)
foreach(f raster:1 raster:2)
  if("${CASE}" STREQUAL "fault.${f}" AND NOT FAILURES)
    file(READ "${case_work}/report.json" j)
    string(JSON raster GET "${j}" calls 0 raster)
    if(f STREQUAL "raster:2" AND NOT raster MATCHES "on a triangle edge .*, 0 interior")
      set(FAILURES "${FAILURES}\nfault.${f}: expected only edge pixels: ${raster}")
    elseif(f STREQUAL "raster:1" AND raster MATCHES ", 0 interior")
      set(FAILURES "${FAILURES}\nfault.${f}: expected interior pixels: ${raster}")
    endif()
  endif()
endforeach()
# The relaxed device model (docs/numerics.md): faults that compute what a real GPU may (a / b as
# a * (1 / b), sqrt as 1 / inversesqrt, a half-pixel edge shift) diverge under the bitwise comparison
# lavapipe gets by default and are accepted as within the spec under --compare relaxed; a 4-ULP error
# and interior raster pixels are beyond it. --strict-math gives the emulator's bits everywhere.
set(device_like intersect:approx-div raygen.shadow:approx-div raygen.shadow:approx-sqrt raygen.refraction:approx-sqrt raster:2 raster:approx-div
    surfaces:approx-div surfaces.hits:approx-div surfaces.hits:approx-sqrt shade:approx-div shade:approx-sqrt
    build:approx-div build:approx-sqrt)
foreach(f IN LISTS device_like)
  string(REGEX REPLACE ":.*" "" pass "${f}")
  diff_case(relaxed.bitwise.${f} glass 64x64 ${f} 4 ${pass})
endforeach()
within_spec_case(relaxed.glass glass 64x64 "${device_like}")
# The hash's cells change under a looser division only now and then: office at 128x128 has two keys.
foreach(f hash:approx-div hash:approx-sqrt)
  diff_case(relaxed.bitwise.${f} office 128x128 ${f} 4 hash)
endforeach()
within_spec_case(relaxed.office office 128x128 "hash:approx-div;hash:approx-sqrt")
diff_case(relaxed.hash:1 glass 64x64 hash:1 4 hash --compare relaxed)
diff_case(relaxed.surfaces:1 glass 64x64 surfaces:1 4 surfaces --compare relaxed)
diff_case(relaxed.shade:1 glass 64x64 shade:1 4 shade --compare relaxed)
# Nodes built without their containment checks: some decision may flip in most folds, but such a
# node must still hold its rays exactly, and these do not.
diff_case(relaxed.build:1 glass 64x64 build:1 4 build --compare relaxed)
diff_case(relaxed.surfaces.hits:1 glass 64x64 surfaces.hits:1 4 surfaces.hits --compare relaxed)
# Every root of the cone-sphere test two ULP high, as a GPU may compute it: the test's slack (2^-17)
# absorbs it, and no traversal flag changes even bitwise.
diff_case(relaxed.traverse:sqrt-high office 64x64 traverse:sqrt-high 0 "")
# The printed test (--cone-test printed) has no slack: the high roots flip a flag, bitwise a divergence
# in traverse, and under --compare relaxed within the spec (the spec model bounds the printed test).
diff_case(relaxed.bitwise.traverse:sqrt-high.printed office 64x64 traverse:sqrt-high 4 traverse --cone-test printed)
diff_case(relaxed.traverse:sqrt-high.printed office 64x64 traverse:sqrt-high 0 "" --compare relaxed --cone-test printed)
diff_case(relaxed.raygen.shadow:2 glass 64x64 raygen.shadow:2 4 raygen.shadow --compare relaxed)
diff_case(relaxed.intersect:ulp4 glass 64x64 intersect:ulp4 4 intersect --compare relaxed)
diff_case(relaxed.raster:1 glass 64x64 raster:1 4 raster --compare relaxed)

# worst_case(NAME SCENE SIZE METHODS [diff options...]): on the simulated worst-conformant device the
# relaxed comparison accepts the frame (exit 0), and each method (or call label) of METHODS has a
# call that differs and is within the spec (a model that saw nothing to judge proves nothing).
function(worst_case name scene size methods)
  begin_case("${name}")
  scene_path("${scene}" path)
  execute_process(COMMAND "${RAYSPACE}" diff "${path}" --data "${DATA}" --size ${size} --backends emu,sim --device-model worst:3
                          --compare relaxed --no-impact --report "${case_work}/report.json" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "all passes equal or within the spec's precision")
    set(FAILURES "${FAILURES}\n${name}: exit ${rc}, expected 0 within the spec: ${out}${err}" PARENT_SCOPE)
    return()
  endif()
  file(READ "${case_work}/report.json" j)
  string(JSON calls LENGTH "${j}" calls)
  math(EXPR last "${calls} - 1")
  set(judged "")
  foreach(k RANGE ${last})
    string(JSON method GET "${j}" calls ${k} method)
    string(JSON label GET "${j}" calls ${k} label)
    string(JSON within ERROR_VARIABLE none GET "${j}" calls ${k} within_spec)
    if(within STREQUAL "ON")
      list(APPEND judged "${method}" "${label}")
    endif()
  endforeach()
  foreach(m IN LISTS methods)
    list(FIND judged "${m}" at)
    if(at EQUAL -1)
      set(FAILURES "${FAILURES}\n${name}: no ${m} call differed within the spec (within: ${judged})" PARENT_SCOPE)
    endif()
  endforeach()
endfunction()

# The traversal lists under the relaxed model (docs/numerics.md), every pass of them run (culling,
# per-polygon heads, per-cell heads of eye rays): on the worst-conformant device the lists' order and
# culling and the walks differ, within the spec (the windows do not differ there; their model's
# known answers are in tests/spec_tl_test.cpp); every planted fault of the four passes is beyond it.
set(tl_all --algo tl --backface-cull on --polygon-heads regular --primary tl --frustum-cull on)
worst_case(relaxed.tl.worst cornell-mirrors 16x16 "tl.lists;tl.trace" ${tl_all})
faults_case(relaxed.faults.tl cornell-mirrors 16x16
            "tl.lists:1;tl.lists:2;tl.lists:3;tl.lists:4;tl.heads:1;tl.heads:2;tl.heads:3;tl.cells:1;tl.cells:2;tl.cells:3;tl.trace:1;tl.trace:2;tl.trace:3;tl.trace:4;tl.trace:5"
            ${tl_all} --compare relaxed)
# The grids under the relaxed model: the planted faults of grid.trace (a perspective cell one column
# off, the least distance too far, a regular walk skipping a z layer, a cell's last triangle
# untested) and of grid.count (a span's last column lost, the distance to the first vertex, a regular
# span one layer short) are each judged beyond the spec, on coarse grids as faults.grid (each fault
# is seen at its own pass on them too). On the worst-conformant device the grids
# differ at grid.count (spans, rectangles and distances computed in double at single precision) and
# the reflection rays' walks through the regular grid at grid.trace, within the spec.
faults_case(relaxed.faults.grid cornell-mirrors 16x16
            "grid.trace:1;grid.trace:2;grid.trace:3;grid.trace:4;grid.count:1;grid.count:2;grid.count:3" --algo grid --compare relaxed
            --grid-cells 64 --grid-regular 16)
worst_case(relaxed.grid.worst cornell-mirrors 16x16 "grid.count;grid.trace.reflection.b1" --algo grid --grid-cells 32)
# Walks through a 3D grid (the eye's, for reflection rays): a step away from the light skipping a
# depth slice misses a triangle every walk to the end tests, beyond the spec; on the worst-conformant
# device the walks differ within it.
faults_case(relaxed.faults.grid.volume cornell-soft 24x24 "grid.trace:5" --algo grid --grid-secondary perspective --grid-cells 32
            --compare relaxed)
worst_case(relaxed.grid.volume.worst cornell-soft 16x16 "grid.trace.reflection.b1" --algo grid --grid-secondary perspective
           --grid-area 12x12x3 --grid-cells 32)
diff_case(strict-math.glass glass 64x64 "" 0 "" --strict-math)
diff_case(strict-math.office office 64x64 "" 0 "" --strict-math)
# The scan-based reduction's fault needs the scan reduction.
diff_case(fault.reduce:2 cornell-mirrors 64x64 reduce:2 4 reduce --reduction scan)
diff_case(fault.rah.traverse:1 cornell-mirrors 64x64 traverse:1 4 traverse --algo rah)
# The fused path, render's default: each level one traverse.compact call on both backends; equal on
# the frames, and each of the pass's faults caught in a whole frame.
diff_case(cornell.crsh.fused cornell-mirrors 96x80 "" 0 "" --path fused)
# The thesis's hash layout (docs/hierarchy.md, "Faithful to the thesis"): other keys, the same on both
# backends; glass brings refraction keys in.
diff_case(cornell.crsh.polar-first cornell-mirrors 64x64 "" 0 "" --hash-order polar-first --hash-bits 8)
diff_case(glass.crsh.polar-first glass 64x64 "" 0 "" --hash-order polar-first --hash-bits 8 --path fused)
diff_case(office.rah.fused office 64x64 "" 0 "" --path fused --algo rah)
diff_case(cornell.rah-quadtree.fused cornell-mirrors 64x64 "" 0 "" --path fused --algo rah-quadtree)
faults_case(faults.fused cornell-mirrors 64x64 "traverse.compact:1;traverse.compact:2;traverse.compact:3;traverse.compact:4;traverse.compact:5;traverse.compact:6;traverse.compact:7" --path fused)
# The same faults in the emulator's workgroup mirror of the kernel: in global memory, which the
# checker does not watch, so the diff must catch them in traverse.compact (:2@emu alone, below, with
# the report's workgroup model).
faults_case(faults.fused.emu cornell-mirrors 64x64 "traverse.compact:1@emu;traverse.compact:3@emu;traverse.compact:4@emu;traverse.compact:5@emu;traverse.compact:6@emu;traverse.compact:7@emu" --path fused)
diff_case(fault.fused.traverse.compact:2@emu cornell-mirrors 64x64 traverse.compact:2@emu 4 traverse.compact --path fused)
# The thesis's rays and objects (docs/hierarchy.md, "Faithful to the thesis"): each switch equal on
# both backends, and a planted raygen.shadow fault still caught under --shadow-rule lit.
foreach(scene cornell-mirrors office)
  diff_case(${scene}.crsh.faithful.shadow_rule ${scene} 64x64 "" 0 "" --shadow-rule lit)
  diff_case(${scene}.crsh.faithful.shadow_bounces ${scene} 64x64 "" 0 "" --shadow-bounces first)
  diff_case(${scene}.crsh.faithful.one_object ${scene} 64x64 "" 0 "" --one-object)
endforeach()
diff_case(fault.faithful.raygen.shadow:1 office 64x64 raygen.shadow:1 4 raygen.shadow --shadow-rule lit)
# --cone-test printed: eq. 3.16 as printed in every traversal pass (traverse.objects, .top, .level; the
# fused path's traverse.compact; rah's top level without the object mask), the same pairs on both
# backends.
diff_case(cornell.crsh.faithful.cone_test cornell-mirrors 64x64 "" 0 "" --cone-test printed)
diff_case(office.crsh.faithful.cone_test.fused office 64x64 "" 0 "" --cone-test printed --path fused)
diff_case(cornell.rah.faithful.cone_test cornell-mirrors 64x64 "" 0 "" --cone-test printed --algo rah)
diff_case(glass.rah.faithful.cone_test.fused glass 64x64 "" 0 "" --cone-test printed --algo rah --path fused)
# --cone-test printed-signed: the same without the absolute value, the same pairs on both backends.
diff_case(cornell.crsh.faithful.cone_test_signed cornell-mirrors 64x64 "" 0 "" --cone-test printed-signed)
diff_case(office.crsh.faithful.cone_test_signed.fused office 64x64 "" 0 "" --cone-test printed-signed --path fused)
# Roger et al.'s leaf test (--leaf-test ray-sphere): each ray of a surviving leaf node against the
# triangle's sphere before its ray-triangle test; the per-pair counts and the hits equal on both
# backends, for each hierarchy, on the passes and on the fused path.
diff_case(cornell.crsh.faithful.leaf_test cornell-mirrors 64x64 "" 0 "" --leaf-test ray-sphere)
diff_case(cornell.rah-quadtree.faithful.leaf_test cornell-mirrors 64x64 "" 0 "" --leaf-test ray-sphere --algo rah-quadtree)
diff_case(office.rah.faithful.leaf_test office 64x64 "" 0 "" --leaf-test ray-sphere --algo rah --path fused)
# --child-merge pairwise: parents united as a balanced tree of unions (build.comp's stack of partial
# unions against the emulator's), equal on both backends for each hierarchy.
diff_case(cornell.crsh.child_merge cornell-mirrors 64x64 "" 0 "" --child-merge pairwise)
diff_case(cornell.rah-quadtree.child_merge cornell-mirrors 64x64 "" 0 "" --child-merge pairwise --algo rah-quadtree)
diff_case(office.crsh.child_merge office 64x64 "" 0 "" --child-merge pairwise --leaf-test ray-sphere --path fused)
# --objects tree: the joint descent's passes (tree.roots, tree.expand, tree.test, intersect.tree) and
# the fused tree.step equal on both backends, with the frame digest of the flat top level; each
# planted fault of the tree kernels caught in its own pass.
foreach(scene cornell-mirrors office)
  foreach(path passes fused)
    diff_case(${scene}.crsh.tree.${path} ${scene} 48x48 "" 0 "" --objects tree --path ${path})
    if("${CASE}" STREQUAL "${scene}.crsh.tree.${path}" AND NOT FAILURES)
      scene_path("${scene}" path_json)
      execute_process(COMMAND "${RAYSPACE}" render "${path_json}" --data "${DATA}" --size 48x48 --backend emu --objects flat
                              --out "${case_work}/flat.png" --stats "${case_work}/flat.json"
                      RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
      file(READ "${case_work}/report.json" j)
      string(JSON tree_digest GET "${j}" digest)
      file(READ "${case_work}/flat.json" fj)
      string(JSON flat_digest GET "${fj}" digest)
      if(NOT rc EQUAL 0 OR NOT "${tree_digest}" STREQUAL "${flat_digest}")
        set(FAILURES "${FAILURES}\n${CASE}: digest ${tree_digest} differs from flat's ${flat_digest} (exit ${rc}: ${err})")
      endif()
    endif()
  endforeach()
endforeach()
faults_case(faults.tree cornell-mirrors 48x48 "tree.roots:1;tree.roots:2;tree.roots:3;tree.expand:1;tree.expand:2;tree.expand:3;tree.test:1;tree.test:2;tree.test:3;intersect.tree:1;intersect.tree:2;intersect.tree:3" --objects tree --path passes)
faults_case(faults.tree.fused cornell-mirrors 48x48 "tree.step:1;tree.step:2;tree.step:3;tree.step:4" --objects tree --path fused)
# --algo tl: the traversal lists' two passes equal on every list count and order, on refraction rays
# (glass) and at another local size; each planted fault caught in its own pass.
foreach(lists 1 2 6 8)
  diff_case(cornell.tl.lists-${lists} cornell-mirrors 48x48 "" 0 "" --algo tl --lists ${lists})
endforeach()
diff_case(cornell.tl.latest-last cornell-mirrors 48x48 "" 0 "" --algo tl --node-order latest-last --local-size 32)
diff_case(glass.tl glass 64x64 "" 0 "" --algo tl --lists 8)
diff_case(office.tl office 64x64 "" 0 "" --algo tl)
faults_case(faults.tl cornell-mirrors 48x48 "tl.lists:1;tl.lists:2;tl.lists:3;tl.trace:1;tl.trace:2;tl.trace:3" --algo tl)
# Back-face culling: the lists' four phases with triangles dropped per list, one-sided walks; the
# culling faults (fronts dropped, backs kept) caught in their passes.
diff_case(cornell.tl.cull cornell-mirrors 48x48 "" 0 "" --algo tl --backface-cull on)
diff_case(glass.tl.cull-8 glass 64x64 "" 0 "" --algo tl --lists 8 --backface-cull on --local-size 32)
faults_case(faults.tl.cull cornell-mirrors 48x48 "tl.lists:4;tl.trace:4" --algo tl --backface-cull on)
# Per-polygon heads: tl.heads' windows and the walks over them equal; each planted fault caught in
# its pass (a flipped plane, the opposite class's facets, a head one element late; the walk taking
# the window of the other side).
diff_case(cornell.tl.heads cornell-mirrors 48x48 "" 0 "" --algo tl --polygon-heads regular)
diff_case(glass.tl.heads-simple-8 glass 64x64 "" 0 "" --algo tl --lists 8 --polygon-heads simple --local-size 32)
diff_case(cornell.tl.heads-cull cornell-mirrors 48x48 "" 0 "" --algo tl --polygon-heads regular --backface-cull on)
faults_case(faults.tl.heads cornell-mirrors 48x48 "tl.heads:1;tl.heads:2;tl.heads:3;tl.trace:5" --algo tl --polygon-heads regular)
# Eye rays traced beside the raster, with and without their cells' windows (partial cells: 40x36);
# each frustum-culling fault caught in its pass (a plane flipped, the next cell's planes, a tail one
# short; an eye ray walking the next cell's window).
diff_case(cornell.tl.primary cornell-mirrors 40x36 "" 0 "" --algo tl --primary tl)
diff_case(cornell.tl.frustum cornell-mirrors 40x36 "" 0 "" --algo tl --primary tl --frustum-cull on --lists 8 --local-size 32)
faults_case(faults.tl.frustum cornell-mirrors 48x48 "tl.cells:1;tl.cells:2;tl.cells:3;tl.trace:6" --algo tl --primary tl --frustum-cull on)
# A traversal-list call saved by a diff replays as the call it was: with its fault reproduced, without
# it equal; the lists' call replays equal.
diff_case(replay.tl cornell-mirrors 48x48 tl.trace:2 4 tl.trace --algo tl --save-inputs "${case_work}/saved")
if("${CASE}" STREQUAL "replay.tl" AND NOT FAILURES)
  file(GLOB trace_dir "${case_work}/saved/*-tl.trace.shadow.b0")
  file(GLOB lists_dir "${case_work}/saved/*-tl.lists")
  if(NOT trace_dir OR NOT lists_dir)
    set(FAILURES "${FAILURES}\nreplay.tl: no saved tl.trace.shadow.b0 or tl.lists call")
  else()
    replay_check("${trace_dir}" 4 "recorded comparison: reproduced")
    replay_check("${trace_dir}" 5 "NOT reproduced, now equal" --inject none)
    replay_check("${lists_dir}" 0 "tl.lists/escapes: [0-9]+ elements equal")
  endif()
endif()

# --algo grid (docs/grids.md): grid.trace equal on the mirrors' point light and many bounces, on
# refraction, on the office's two lights, on area lights (their shadow rays through the lights' 3D
# perspective grids) and with coarse and fine grids; each planted fault caught in grid.trace.
diff_case(cornell.grid cornell-mirrors 48x48 "" 0 "" --algo grid)
diff_case(glass.grid glass 64x64 "" 0 "" --algo grid --grid-cells 64 --grid-regular 16 --local-size 32)
# Coarse grids: the office's two lights' grids as three calls; the default resolution is cornell.grid's.
diff_case(office.grid office 64x64 "" 0 "" --algo grid --grid-cells 64 --grid-regular 16)
diff_case(area.grid area-shapes 48x48 "" 0 "" --algo grid --grid-regular 100)
# The area lights' 3D perspective grids coarse and close to the lights (many faces and slices per
# ray), with front-face culling, and their shadow rays through the regular grid instead.
diff_case(area.grid.coarse area-shapes 48x48 "" 0 "" --algo grid --grid-area 16x16x3 --grid-area-near 1)
diff_case(area.grid.closed area-shapes 40x40 "" 0 "" --algo grid --grid-area 50x50x6 --closed-models)
diff_case(area.grid.regular area-shapes 40x40 "" 0 "" --algo grid --grid-area regular)
# Reflection and refraction rays through the 3D perspective grid about the eye (closest hits).
diff_case(cornell.grid.secondary cornell-mirrors 48x48 "" 0 "" --algo grid --grid-secondary perspective --grid-area 24x24x5)
diff_case(glass.grid.secondary glass 48x48 "" 0 "" --algo grid --grid-secondary perspective)
diff_case(fault.grid.grid.trace:6 cornell-mirrors 48x48 grid.trace:6 4 grid.trace --algo grid --grid-secondary perspective --grid-area 24x24x5)
diff_case(fault.grid.grid.trace:5 area-shapes 48x48 grid.trace:5 4 grid.trace --algo grid --grid-area 16x16x3 --grid-area-near 1)
diff_case(cornell.grid.closed cornell-mirrors 48x48 "" 0 "" --algo grid --closed-models)
diff_case(cornell.grid.primary cornell-mirrors 40x36 "" 0 "" --algo grid --primary grid)
# A grid call saved by a diff replays as the call it was: with its fault reproduced, without it equal.
diff_case(replay.grid cornell-mirrors 32x32 grid.trace:3 4 grid.trace --algo grid --save-inputs "${case_work}/saved")
if("${CASE}" STREQUAL "replay.grid" AND NOT FAILURES)
  file(GLOB trace_dir "${case_work}/saved/*-grid.trace.reflection.b1")
  if(NOT trace_dir)
    set(FAILURES "${FAILURES}\nreplay.grid: no saved grid.trace.reflection.b1 call")
  else()
    replay_check("${trace_dir}" 4 "recorded comparison: reproduced")
    replay_check("${trace_dir}" 5 "NOT reproduced, now equal" --inject none)
  endif()
endif()
# The grids' build as kernels (grid.count, grid.emit, the sort, grid.cells): each planted fault is
# caught in its own pass, before grid.trace reads the grids.
# Coarse grids (a third of the time; the default resolution is cornell.grid's): each fault still
# caught in its own pass.
faults_case(faults.grid cornell-mirrors 48x48 "grid.trace:1;grid.trace:2;grid.trace:3;grid.trace:4;grid.count:1;grid.count:2;grid.count:3;grid.emit:1;grid.emit:2;grid.emit:3;grid.cells:1;grid.cells:2;grid.cells:3" --algo grid --grid-cells 64 --grid-regular 16)
# The same on a scene of area lights only (the regular grid binned first) and with the eye's grid.
diff_case(fault.grid.volume.grid.count:1 area-shapes 40x40 grid.count:1 4 grid.count --algo grid --grid-area 16x16x3 --grid-area-near 1 --grid-regular 8)
diff_case(fault.grid.primary.grid.emit:2 cornell-mirrors 40x36 grid.emit:2 4 grid.emit --algo grid --primary grid)
# The emulator runs traverse.compact on its workgroup mirror when the run asks for the workgroup
# model (the checker, on by default in diff; a schedule other than forward; an @emu fault) and on
# SIMD lanes otherwise: both must equal the kernel, and the report says which ran.
diff_case(cornell.crsh.fused.lanes cornell-mirrors 64x64 "" 0 "" --path fused --no-check-workgroups)
diff_case(cornell.crsh.fused.schedule.reverse cornell-mirrors 64x64 "" 0 "" --path fused --schedule reverse)
diff_case(cornell.crsh.fused.schedule.random:7 cornell-mirrors 64x64 "" 0 "" --path fused --schedule random:7 --no-check-workgroups)
diff_case(office.crsh.fused.schedule.random:3 office 64x64 "" 0 "" --path fused --schedule random:3 --local-size 32)
foreach(c cornell.crsh.fused.lanes cornell.crsh.fused.schedule.reverse cornell.crsh.fused.schedule.random:7
          office.crsh.fused.schedule.random:3 fault.fused.traverse.compact:2@emu)
  if("${CASE}" STREQUAL "${c}" AND NOT FAILURES)
    file(READ "${case_work}/report.json" j)
    string(JSON model GET "${j}" workgroup_model)  # a JSON boolean reads as ON or OFF
    set(expect ON)
    if(c MATCHES "lanes$")
      set(expect OFF)
    endif()
    if(NOT model STREQUAL expect)
      set(FAILURES "${FAILURES}\n${c}: workgroup_model ${model}, expected ${expect}")
    endif()
  endif()
endforeach()

# The workgroup faults (kFault* in rayspace/contract.h), planted in workgroup.glsl's
# WorkgroupInclusiveAdd or in its emulated mirror. In the kernel the diff must catch them in their
# pass; lavapipe runs the divergent barrier benignly (its SIMD code reaches the barrier on every
# path), which the diff must say. In the emulated kernel the workgroup checker must name them first.
set(workgroup_faults
    trim:dropped-barrier trim:divergent-barrier trim:subgroup-32 trim:shared-off-by-one trim:workgroup-offset
    compress:dropped-barrier compress:divergent-barrier compress:subgroup-32 compress:shared-off-by-one
    sort:dropped-barrier sort:divergent-barrier sort:subgroup-32 sort:shared-off-by-one
    decompress:dropped-barrier decompress:divergent-barrier decompress:subgroup-32 decompress:shared-off-by-one
    reduce:dropped-barrier reduce:divergent-barrier reduce:subgroup-32 reduce:shared-off-by-one)
set(kernel_workgroup_faults "")
foreach(f IN LISTS workgroup_faults)
  string(REGEX REPLACE ":.*" "" pass "${f}")
  if(f MATCHES "divergent-barrier")
    diff_case(fault.${f} cornell-mirrors 64x64 ${f} 0 "")  # run benignly by lavapipe, and said so
  else()
    list(APPEND kernel_workgroup_faults ${f})
  endif()
  if(f MATCHES "workgroup-offset")
    # In global memory, which the checker does not watch: the diff must catch the emulated kernel's
    # fault as it catches the Vulkan one's.
    diff_case(fault.${f}@emu cornell-mirrors 64x64 ${f}@emu 4 ${pass})
  else()
    checker_case(fault.${f}@emu cornell-mirrors 64x64 ${f}@emu ${pass})
  endif()
endforeach()
faults_case(faults.workgroup cornell-mirrors 64x64 "${kernel_workgroup_faults}")
# The faults for the simulated GPU's checkers, in trim's kernel alone (a write-write race of equal
# values, a load past the end whose value goes unused, an undefined offset that lavapipe's compiler
# makes zero, the right one, slots by local index on lavapipe's linear subgroups): lavapipe runs each
# benignly and the diff must say so; on the simulator each is caught by its checker or, for
# linear-lanes, by a shuffled subgroup layout (tests/cli_simulate.cmake).
foreach(f trim:global-race trim:out-of-bounds trim:undefined-value trim:linear-lanes trim:far-out-of-bounds)
  diff_case(fault.${f} cornell-mirrors 16x16 ${f} 0 "" --algo brute)
endforeach()
# GPU-assisted validation (--validate; the suite's RAYSPACE_VALIDATE=1 leaves it off, so the case
# above is benign): a load a block past the flags, beyond the buffer's 256 guard bytes, is the
# layer's own finding, naming the descriptor and the byte.
function(gpu_assisted_case name)
  begin_case("${name}")
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --algo brute --validate
                          --inject trim:far-out-of-bounds --no-impact
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0 OR NOT err MATCHES "pass trim: .*Validation Error: .*access out of bounds\. Descriptor size is [0-9]+ and highest byte accessed was [0-9]+")
    set(FAILURES "${FAILURES}\n${name}: exit ${rc}, expected the layer's out-of-bounds finding in trim: ${out}${err}" PARENT_SCOPE)
  endif()
endfunction()
gpu_assisted_case(validate.gpu-assisted)

# Saved inputs replay to the same comparison: with the fault it diverges again ("reproduced"),
# without it the pass is equal, which differs from the recording (exit 5).
if("${CASE}" STREQUAL "replay.save")
  file(REMOVE_RECURSE "${WORK}/saved")
endif()
# What a divergence does to the picture: faults that change hits, and ones that only regroup rays.
# traverse:1 drops top-level pairs: in the office some of them held hits, in the Cornell box none.
impact_case(impact.traverse:1 office 64x64 traverse:1 changes)
impact_case(impact.intersect:1 cornell-mirrors 64x64 intersect:1 changes)
impact_case(impact.sim.intersect:1 cornell-mirrors 16x16 intersect:1 changes --backends emu,sim)
impact_case(impact.invisible.traverse:1 cornell-mirrors 64x64 traverse:1 invisible)
impact_case(impact.invisible.hash:1 cornell-mirrors 64x64 hash:1 invisible)
impact_case(impact.invisible.tree.roots:3 cornell-mirrors 48x48 tree.roots:3 invisible --objects tree --path passes)
diff_case(replay.save cornell-mirrors 64x64 traverse:1 4 traverse --save-inputs "${WORK}/saved")
if("${CASE}" STREQUAL "replay.save" AND NOT case_out MATCHES "inputs saved: [0-9]+ calls in ${WORK}/saved")
  set(FAILURES "${FAILURES}\nreplay.save: the summary does not say where the inputs went")
endif()
# The fault the diff planted is recorded with each call and planted again; --inject none replays the
# call without it: the recorded divergence is gone, which the replay says, and its report is written.
replay_saved(replay.fault "*-traverse.L2.shadow.b0" 4 "recorded comparison: reproduced")
replay_saved(replay.clean "*-traverse.L2.shadow.b0" 5 "NOT reproduced, now equal: the recorded divergence is gone"
             --inject none --report "${WORK}/replay-clean.json")
if("${CASE}" STREQUAL "replay.clean" AND NOT FAILURES)
  file(READ "${WORK}/replay-clean.json" j)
  string(JSON now_equal GET "${j}" recorded now_equal)
  if(NOT now_equal)
    set(FAILURES "${FAILURES}\nreplay.clean: the report does not record 'now_equal'")
  endif()
endif()
replay_saved(replay.raster "*-raster" 0 "raster/prim: 4096 elements equal")
# A device-like raster (edges shifted) replayed under the relaxed comparison: within the spec, which
# the equal comparison recorded at save time does not reproduce.
replay_saved(replay.raster.relaxed "*-raster" 5 "every difference is within the spec's precision" --inject raster:2 --compare relaxed)
# --split-bytes reaches replay: trim's fault 2 (the carry between parts dropped) shows only when
# the stream is split, so the same saved call is refused with the fault that cannot fire (exit 2,
# no verdict) without the option and diverges with it.
replay_saved(replay.unsplit "*-trim.shadow.b0" 2 "error: the planted fault trim:2 cannot fire: no buffer was split or paged"
             --inject trim:2)
replay_saved(replay.split "*-trim.shadow.b0" 5 "NOT reproduced" --inject trim:2 --split-bytes 4096)
# traverse.compact (the traversal fused with its reduction) on single calls: these cases replay the
# top-level and level calls replay.save wrote (a pass-by-pass diff) as traverse.compact calls, which
# take the same inputs (the fused.* cases above diff it in whole frames). Without a fault both backends give the same survivors and tests; each planted fault
# must make the replay diverge in traverse.compact's pairs or tested count.
# compact_case(NAME PATTERN METHOD INJECT EXPECT_RC [replay options...])
function(compact_case name pattern method inject expect_rc)
  begin_saved_case("${name}" "${pattern}")
  file(COPY "${dir}/" DESTINATION "${case_work}/call")
  file(REMOVE "${case_work}/call/comparison.json")  # recorded for the slots, not for the fused call
  file(READ "${case_work}/call/pass.json" pass)
  string(JSON pass SET "${pass}" method "\"${method}\"")
  file(WRITE "${case_work}/call/pass.json" "${pass}")
  set(args "")
  if(inject)
    set(args --inject ${inject})
  endif()
  execute_process(COMMAND "${RAYSPACE}" replay "${case_work}/call" ${args} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL expect_rc OR NOT out MATCHES "rayspace replay: traverse.compact \\(${method}\\)")
    set(FAILURES "${FAILURES}\n${name}: exit ${rc} (expected ${expect_rc}): ${out}${err}" PARENT_SCOPE)
  elseif(expect_rc EQUAL 0 AND NOT out MATCHES "traverse.compact/pairs: [0-9]+ elements equal.*traverse.compact/tested: 1 elements equal")
    set(FAILURES "${FAILURES}\n${name}: expected equal pairs and tested count: ${out}" PARENT_SCOPE)
  elseif(expect_rc EQUAL 4 AND NOT out MATCHES "traverse.compact/(pairs|tested): ([0-9]+ of [0-9]+ elements differ|sizes differ)")
    set(FAILURES "${FAILURES}\n${name}: no differing traverse.compact buffer named: ${out}" PARENT_SCOPE)
  endif()
endfunction()
compact_case(compact.top "*-traverse.L2.shadow.b0" traverse.compact.top "" 0)
compact_case(compact.level "*-traverse.L1.shadow.b0" traverse.compact.level "" 0)
compact_case(compact.level.local-size-7 "*-traverse.L1.shadow.b0" traverse.compact.level "" 0 --local-size 7)
foreach(f traverse.compact:1 traverse.compact:2 traverse.compact:3 traverse.compact:4)
  compact_case(fault.${f} "*-traverse.L2.shadow.b0" traverse.compact.top ${f} 4)
  compact_case(fault.level.${f} "*-traverse.L1.shadow.b0" traverse.compact.level ${f} 4)
endforeach()
compact_case(fault.level.traverse.compact:6 "*-traverse.L1.shadow.b0" traverse.compact.level traverse.compact:6 4)
compact_case(fault.top.traverse.compact:7 "*-traverse.L2.shadow.b0" traverse.compact.top traverse.compact:7 4)

case_selected(replay.missing run)
if(run)
  replay_check("${case_work}/no-such-dir" 2 "pass.json: cannot open")
endif()
case_selected(replay.truncated run)
if(run)
  file(MAKE_DIRECTORY "${case_work}/bad-set")
  file(WRITE "${case_work}/bad-set/pass.json" "{\"method\": \"traverse.top\", \"buffers\": {\"top\": {\"type\": \"cone_node\", \"count\": 3}}}")
  file(WRITE "${case_work}/bad-set/top.bin" "short")
  replay_check("${case_work}/bad-set" 2 "top.bin: 5 bytes, expected 3 elements of 48 bytes")
endif()
# A hand-edited copy of a saved call: a comparison.json of another shape, a frame no render could
# have made (every byte 'A': a 1094795585 x 1094795585 image) and triangles beyond the coordinate
# domain (every byte 0x7F: 3.4e38) are bad input naming the file.
case_selected(replay.edited run)
set(cli_diff_after_save ${cli_diff_after_save} replay.edited)
if(run)
  file(GLOB raster_dir "${WORK}/saved/*-raster")
  file(COPY "${raster_dir}/" DESTINATION "${case_work}/set")
  file(WRITE "${case_work}/set/comparison.json" "[]")
  replay_check("${case_work}/set" 2 "comparison.json: expected a JSON object, got array")
  file(WRITE "${case_work}/set/comparison.json" "{\"equal\": true, \"buffers\": [1]}")
  replay_check("${case_work}/set" 2 "comparison.json: buffers.0. must be an object")
  file(WRITE "${case_work}/set/comparison.json" "{\"inject\": 5}")
  replay_check("${case_work}/set" 2 "comparison.json: 'inject' must be a string")
  string(REPEAT "A" 192 frame)
  file(WRITE "${case_work}/set/frame.bin" "${frame}")
  replay_check("${case_work}/set" 2 "frame.bin: image size 1094795585 x 1094795585 out of range")
  file(READ "${case_work}/set/pass.json" pass)
  string(JSON count GET "${pass}" buffers scene.triangles count)
  math(EXPR bytes "${count} * 48")
  string(ASCII 127 del)
  string(REPEAT "${del}" ${bytes} tris)
  file(WRITE "${case_work}/set/scene.triangles.bin" "${tris}")
  replay_check("${case_work}/set" 2 "scene.triangles.bin: triangle 0 leaves the coordinate domain")
endif()

# A call that pass.json names with an unknown method, and a saved raygen call whose ray kind was edited:
# bad input naming the saved call's file or directory.
case_selected(replay.unknown-method run)
if(run)
  file(MAKE_DIRECTORY "${case_work}/warp")
  file(WRITE "${case_work}/warp/pass.json" "{\"method\": \"warp\", \"buffers\": {}}")
  execute_process(COMMAND "${RAYSPACE}" replay "${case_work}/warp" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "^rayspace: error: ${case_work}/warp/pass.json: unknown pass method 'warp'[^\n]*\n$")
    set(FAILURES "${FAILURES}\nreplay.unknown-method: exit ${rc}, stderr '${err}'")
  endif()
endif()
case_selected(replay.bad-kind run)
set(cli_diff_after_save ${cli_diff_after_save} replay.bad-kind)
if(run)
  file(GLOB raygen_dir "${WORK}/saved/*-raygen.shadow.b0")
  file(COPY "${raygen_dir}/" DESTINATION "${case_work}/set")
  file(READ "${case_work}/set/pass.json" pass)
  string(JSON pass SET "${pass}" scalars kind 9)
  file(WRITE "${case_work}/set/pass.json" "${pass}")
  execute_process(COMMAND "${RAYSPACE}" replay "${case_work}/set" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "^rayspace: error: ${case_work}/set: [^\n]*'kind' = 9[^\n]*\n$")
    set(FAILURES "${FAILURES}\nreplay.bad-kind: exit ${rc}, stderr '${err}'")
  endif()
endif()

# replay stands alone: the diff records every option that changes what a call computes (here
# --split-bytes, without which trim's fault 2 cannot fire, and --inject) beside each saved call, and
# replay applies them, so that the divergence reproduces without repeating them.
case_selected(replay.recorded-options run)
if(run)
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 96x96 --split-bytes 163840
                          --inject trim:2 --save-inputs "${case_work}/saved" --report "${case_work}/report.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  file(GLOB trim_dir "${case_work}/saved/*-trim.shadow.b0")
  if(NOT rc EQUAL 4 OR NOT trim_dir)
    set(FAILURES "${FAILURES}\nreplay.recorded-options: diff exit ${rc}, saved trim call '${trim_dir}': ${err}")
  else()
    execute_process(COMMAND "${RAYSPACE}" replay "${trim_dir}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 4 OR NOT out MATCHES "as recorded: --split-bytes 163840 --inject 'trim:2'"
       OR NOT out MATCHES "recorded comparison: reproduced" OR NOT err MATCHES "rayspace replay: divergent")
      set(FAILURES "${FAILURES}\nreplay.recorded-options: replay exit ${rc}: ${out}${err}")
    endif()
  endif()
endif()

# A fault that cannot fire in the run's configuration (trim's fault 2 needs split buffers): exit 2 and
# one error line naming it, no verdict ("equal" or "executed benignly") and no report.
case_selected(fault.trim:2.unsplit run)
if(run)
  file(REMOVE "${case_work}/report.json")
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 64x64 --inject trim:2
                          --report "${case_work}/report.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR out MATCHES "benignly|equal" OR EXISTS "${case_work}/report.json"
     OR NOT err STREQUAL "rayspace: error: the planted fault trim:2 cannot fire: no buffer was split or paged (give --split-bytes)\n")
    set(FAILURES "${FAILURES}\nfault.trim:2.unsplit: exit ${rc}, stderr '${err}', stdout ${out}")
  endif()
endif()
# The same for a fault in a pass the run's path does not have: the fused path runs no reduce.
case_selected(fault.reduce:subgroup-32.fused run)
if(run)
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 32x32 --path fused --inject reduce:subgroup-32
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR out MATCHES "benignly|equal"
     OR NOT err STREQUAL "rayspace: error: the planted fault reduce:subgroup-32 cannot fire: pass reduce did not run\n")
    set(FAILURES "${FAILURES}\nfault.reduce:subgroup-32.fused: exit ${rc}, stderr '${err}', stdout ${out}")
  endif()
endif()

# Outputs: --save-inputs must name a new or empty directory; the report's path is checked before the
# frame (with --device 63 as the next error, the message must name the report); a report whose late
# write fails (a file size limit) keeps the divergence's exit 4; --report - is standard output.
case_selected(save-inputs.not-empty run)
if(run)
  file(WRITE "${case_work}/used/0000-raster/pass.json" "{}")
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --save-inputs "${case_work}/used"
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "^rayspace: error: --save-inputs ${case_work}/used: the directory is not empty[^\n]*\n$")
    set(FAILURES "${FAILURES}\nsave-inputs.not-empty: exit ${rc}, stderr '${err}'")
  endif()
endif()
# --save-inputs creates its directory, never the parents: a missing parent is exit 2 before the frame.
case_selected(save-inputs.nodir run)
if(run)
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --save-inputs "${case_work}/nodir/saved"
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR EXISTS "${case_work}/nodir"
     OR NOT err MATCHES "^rayspace: error: --save-inputs ${case_work}/nodir/saved: the directory ${case_work}/nodir does not exist[^\n]*\n$")
    set(FAILURES "${FAILURES}\nsave-inputs.nodir: exit ${rc}, stderr '${err}'")
  endif()
endif()
# SIGTERM mid-frame leaves --save-inputs as it was found (gone, or empty), never half-filled, so that
# the same command runs again.
case_selected(save-inputs.sigterm run)
if(run)
  foreach(start new empty)
    file(REMOVE_RECURSE "${case_work}/calls")
    if(start STREQUAL "empty")
      file(MAKE_DIRECTORY "${case_work}/calls")
    endif()
    execute_process(COMMAND timeout -s TERM 2 "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 512x512
                            --save-inputs "${case_work}/calls"
                    RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
    # What threads wrote after the handler emptied it, the cleaner it forks removes once the process
    # is gone: polled for up to 10 s.
    foreach(i RANGE 50)
      file(GLOB left "${case_work}/calls/*" "${case_work}/calls/.*")
      if(NOT left AND (start STREQUAL "empty" OR NOT EXISTS "${case_work}/calls"))
        break()
      endif()
      execute_process(COMMAND sleep 0.2)
    endforeach()
    set(state "gone")
    if(EXISTS "${case_work}/calls")
      set(state "there")
    endif()
    if(NOT rc EQUAL 124 OR left OR (start STREQUAL "new" AND EXISTS "${case_work}/calls")
       OR (start STREQUAL "empty" AND NOT EXISTS "${case_work}/calls"))
      set(FAILURES "${FAILURES}\nsave-inputs.sigterm (${start}): exit ${rc} (124: terminated), directory ${state}, left: ${left}")
    endif()
  endforeach()
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --save-inputs "${case_work}/calls"
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  file(GLOB saved "${case_work}/calls/*")
  if(NOT rc EQUAL 0 OR NOT saved)
    set(FAILURES "${FAILURES}\nsave-inputs.sigterm: the rerun: exit ${rc}, saved: ${saved}: ${err}")
  endif()
endif()
case_selected(report.nodir run)
if(run)
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --report "${case_work}/nodir/r.json"
                          --device 63
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "^rayspace: error: ${case_work}/nodir/r.json: cannot write the report[^\n]*\n$")
    set(FAILURES "${FAILURES}\nreport.nodir: exit ${rc}, stderr '${err}'")
  endif()
endif()
case_selected(report.late-failure run)
if(run)
  execute_process(COMMAND sh -c "trap '' XFSZ\nulimit -f 4\nexec \"$0\" \"$@\"" "${RAYSPACE}" diff
                          "${SRC}/scenes/cornell-mirrors.json" --size 32x32 --inject raster:1 --report "${case_work}/r.json"
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  file(GLOB left "${case_work}/r.json" "${case_work}/.r.json.tmp-*")
  if(NOT rc EQUAL 4 OR NOT err MATCHES "r.json: cannot write the report: File too large" OR left)
    set(FAILURES "${FAILURES}\nreport.late-failure: exit ${rc} (expected 4), left behind '${left}', stderr '${err}'")
  endif()
endif()
case_selected(report.stdout run)
if(run)
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 32x32 --report -
                  WORKING_DIRECTORY "${case_work}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(JSON equal ERROR_VARIABLE jerr GET "${out}" equal)
  if(NOT rc EQUAL 0 OR jerr OR NOT equal OR EXISTS "${case_work}/-")
    set(FAILURES "${FAILURES}\nreport.stdout: exit ${rc}, 'equal' ${equal} (${jerr}): ${out}${err}")
  endif()
endif()

# --progress with stderr not a terminal: a plain line per pass, "k of n" up to "n of n" with the
# elapsed time and an ETA on the lines before the last, the impact's frames labelled; none on stdout.
case_selected(progress run)
if(run)
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 32x32 --inject intersect:1 --progress
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(REGEX MATCH "\\[rayspace\\] ([0-9]+) of ([0-9]+) resolve [^\n]*elapsed" last "${err}")
  if(NOT rc EQUAL 4 OR NOT last OR NOT CMAKE_MATCH_1 EQUAL CMAKE_MATCH_2
     OR NOT err MATCHES "\\[rayspace\\] 1 of [0-9]+ prep [^\n]*; elapsed [0-9.]+ s, ETA [0-9.]+ s\n"
     OR NOT err MATCHES "\\[rayspace\\] impact, the emulator alone: 1 of "
     OR NOT err MATCHES "\\[rayspace\\] impact, the vulkan backend alone: [0-9]+ of [0-9]+ resolve" OR out MATCHES "rayspace\\]")
    set(FAILURES "${FAILURES}\n--progress: exit ${rc}, stdout:\n${out}\nstderr:\n${err}")
  endif()
endif()

# A device index that does not exist is bad input: exit 2 and one line naming the option.
case_selected(bad-device run)
if(run)
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --device 63
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "--device 63")
    set(FAILURES "${FAILURES}\n--device 63: exit ${rc}, stderr '${err}'")
  endif()
endif()

if(DEFINED CASE)
  if(NOT matched)
    message(FATAL_ERROR "cli_diff.cmake: no case named '${CASE}'; cases: ${cli_diff_cases}")
  endif()
  if(FAILURES)
    message(FATAL_ERROR "${FAILURES}")
  endif()
  if(NOT skipped)
    message(STATUS "diff ${CASE}: as expected")
  endif()
endif()
