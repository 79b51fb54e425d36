# `rayspace simulate`: exported reproducers run on the simulated GPU give the read-backs lavapipe gave.
#   PART=sample (default tier)  one exported call of every pass of a 16x16 cornell-mirrors diff, each
#                               equal; a call exported with a planted fault differs (exit 4, naming the
#                               read-back and word); one exported with trim's global race is exit 6
#                               naming racecheck (0 with it off), as is its replay --backends emu,sim;
#                               a user's reduce kernel's unreached lines are named, and --reduction
#                               scan reaches the first of them
#                               a directory that is no export is exit 2, one line
#   PART=all (full tier)        every exported call of 32x32 diffs of cornell-mirrors and office
#   PART=backend (default tier) diff --backends emu,sim on a 16x16 cornell-mirrors pass by pass, and
#                               fused under a random schedule at subgroup size 4, all equal; render --backend sim gives the emulator's
#                               digest, and refuses the simulated GPU's options on other backends; a planted reduce
#                               fault diverges; a workgroup past --step-limit is exit 7, not a divergence; every
#                               planted GPU fault is caught on the kernel by its checker (exit 6)
#   PART=backend-all (full)     the same diffs at 32x32 on cornell-mirrors, the quadtree too, subgroup
#                               sizes 1, 4, 32 and 64, the grids at 16x16, and office fused and pass by pass;
#                               each planted fault not caught by its checker when --sim-checks leaves it out
#   PART=schedules (full)       cornell-mirrors at 64x64 under SCHEDULE (forward, reverse and three random
#                               ones, a test each) at subgroup sizes 4, 8, 32 and 64: all equal
#   PART=device-model (full)    diff and render under the worst-conformant device (render's digest not the
#                               emulator's, lavapipe's model's equal to it); the subgroup layouts' findings
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch> -DPART=<part> -P cli_simulate.cmake
cmake_minimum_required(VERSION 3.19)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/ex")
set(failures "")

# Saves every call of a diff of SCENE at SIZE under WORK/NAME; sets `calls` to the saved directories.
function(save name scene size)
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/${scene}.json" --size ${size} --save-inputs "${WORK}/${name}"
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  file(GLOB dirs "${WORK}/${name}/*")
  if(NOT rc EQUAL 0 OR NOT dirs)
    message(FATAL_ERROR "diff ${scene} --save-inputs: exit ${rc}: ${err}")
  endif()
  set(calls "${dirs}" PARENT_SCOPE)
endfunction()

# Exports CALL (ARGN: export options) to WORK/ex/<diff>-<call>; sets `out` ("" when export refuses it: the raster).
function(export_call call)
  get_filename_component(n "${call}" NAME)
  get_filename_component(saved "${call}" DIRECTORY)
  get_filename_component(saved "${saved}" NAME)
  set(out "${WORK}/ex/${saved}-${n}${ARGN}")
  string(REGEX REPLACE "[^A-Za-z0-9._/-]" "_" out "${out}")
  execute_process(COMMAND "${RAYSPACE}" export "${call}" --out "${out}" ${ARGN} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    if(NOT err MATCHES "raster")
      set(failures "${failures}\nexport ${n}: exit ${rc}: ${err}" PARENT_SCOPE)
    endif()
    set(out "" PARENT_SCOPE)
    return()
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

# Runs `diff ARGN --report WORK/NAME.json`; sets rc, out, err and j (the report's text, "" without one).
function(diff_with_report name)
  file(REMOVE "${WORK}/${name}.json")
  execute_process(COMMAND "${RAYSPACE}" diff ${ARGN} --report "${WORK}/${name}.json" RESULT_VARIABLE r OUTPUT_VARIABLE o ERROR_VARIABLE e)
  set(text "")
  if(EXISTS "${WORK}/${name}.json")
    file(READ "${WORK}/${name}.json" text)
  endif()
  set(rc "${r}" PARENT_SCOPE)
  set(out "${o}" PARENT_SCOPE)
  set(err "${e}" PARENT_SCOPE)
  set(j "${text}" PARENT_SCOPE)
endfunction()

function(simulate_equal dir)
  execute_process(COMMAND "${RAYSPACE}" simulate "${dir}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "\nequal: every read-back has the expected bytes\n")
    set(failures "${failures}\nsimulate ${dir}: exit ${rc}: ${out}${err}" PARENT_SCOPE)
  endif()
endfunction()

if(PART STREQUAL "sample")
  save(cornell cornell-mirrors 16x16)
  set(seen "")
  set(n 0)
  foreach(call ${calls})
    file(READ "${call}/comparison.json" j)
    string(JSON pass GET "${j}" pass)
    if(pass IN_LIST seen OR pass STREQUAL "raster")
      continue()
    endif()
    list(APPEND seen "${pass}")
    export_call("${call}")
    if(out)
      simulate_equal("${out}")
      math(EXPR n "${n} + 1")
    endif()
  endforeach()
  if(n LESS 12)
    set(failures "${failures}\nonly ${n} passes exported: ${seen}")
  endif()
  # A planted fault in the exported kernel: the simulator runs it and the read-back differs.
  file(GLOB reduce "${WORK}/cornell/*-reduce.*")
  list(GET reduce 0 reduce)
  export_call("${reduce}" --inject reduce:1)
  execute_process(COMMAND "${RAYSPACE}" simulate "${out}" RESULT_VARIABLE rc OUTPUT_VARIABLE sout ERROR_VARIABLE err)
  if(NOT rc EQUAL 4 OR NOT sout MATCHES "\\(reduce/5/Out\\): word [0-9]+: expected 0x[0-9a-f]+ got 0x[0-9a-f]+\n"
     OR NOT err MATCHES "a read-back differs from the expected bytes")
    set(failures "${failures}\nsimulate with reduce:1 planted: exit ${rc}, expected 4 naming the differing word: ${sout}${err}")
  endif()
  # A checker's finding on an exported kernel: a trim call exported with the global race planted
  # (lavapipe runs it benignly, so its read-backs are the right ones) is exit 6 naming racecheck, and
  # equal with racecheck left out. replay --backends emu,sim of the saved call stops the same way.
  file(GLOB trim "${WORK}/cornell/*-trim.*")
  list(GET trim 0 trim)
  export_call("${trim}" --inject trim:global-race)
  execute_process(COMMAND "${RAYSPACE}" simulate "${out}" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 6 OR NOT err MATCHES "racecheck found a fault of the kernel: trim trim.comp:[0-9]+: racecheck: invocation ")
    set(failures "${failures}\nsimulate with trim:global-race planted: exit ${rc}, expected 6 naming racecheck: ${err}")
  endif()
  execute_process(COMMAND "${RAYSPACE}" simulate "${out}" --sim-checks initcheck,synccheck,memcheck RESULT_VARIABLE rc OUTPUT_VARIABLE sout
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT sout MATCHES "\nequal: every read-back has the expected bytes\n")
    set(failures "${failures}\nsimulate with trim:global-race planted, racecheck off: exit ${rc}, expected 0: ${sout}${err}")
  endif()
  execute_process(COMMAND "${RAYSPACE}" replay "${trim}" --backends emu,sim --inject trim:global-race --report "${WORK}/replay.json"
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  set(named "")
  if(EXISTS "${WORK}/replay.json")
    file(READ "${WORK}/replay.json" j)
    string(JSON named ERROR_VARIABLE jerr GET "${j}" simulator_checker checker)
  endif()
  if(NOT rc EQUAL 6 OR NOT err MATCHES "\n  racecheck on the kernel of trim: trim trim.comp:[0-9]+: racecheck: " OR NOT named STREQUAL "racecheck")
    set(failures "${failures}\nreplay --backends emu,sim --inject trim:global-race: exit ${rc}, expected 6 naming racecheck: ${err}")
  endif()
  execute_process(COMMAND "${RAYSPACE}" replay "${trim}" --backends emu,sim RESULT_VARIABLE rc OUTPUT_VARIABLE sout ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT sout MATCHES "on rayspace simulator" OR NOT sout MATCHES "\n  equal\n")
    set(failures "${failures}\nreplay --backends emu,sim: exit ${rc}, expected 0 on the simulator: ${sout}${err}")
  endif()
  # Coverage of a user's kernel: the lines a run never reached are named, and the option that takes
  # the other path reaches them (the scan-based reduction runs the phases the hierarchical one skips).
  file(COPY "${SRC}/gpu/shaders/reduce.comp" DESTINATION "${WORK}")
  foreach(run default scan)
    set(extra "")
    if(run STREQUAL "scan")
      set(extra --reduction scan)
    endif()
    execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 8x8 --backends emu,sim
                            --kernel "reduce=${WORK}/reduce.comp" ${extra} --report "${WORK}/coverage_${run}.json"
                    RESULT_VARIABLE rc OUTPUT_VARIABLE sout ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT sout MATCHES "\n  coverage of --kernel reduce on the simulated GPU: [0-9]+ of [0-9]+ lines reached \\([0-9]+ %\\); never reached, so not tested by this run: reduce.comp:")
      set(failures "${failures}\ndiff --kernel reduce=reduce.comp ${extra}: exit ${rc}, no coverage line naming reduce.comp's missed lines: ${sout}${err}")
      break()
    endif()
    file(READ "${WORK}/coverage_${run}.json" j)
    string(JSON missed_${run} GET "${j}" kernel_coverage 0 missed)
  endforeach()
  if(DEFINED missed_default AND DEFINED missed_scan)
    string(JSON first GET "${missed_default}" 0)
    if(missed_scan MATCHES "\"${first}\"")
      set(failures "${failures}\ncoverage: --reduction scan does not reach ${first}, which the default run missed: ${missed_scan}")
    endif()
  endif()
  # Not an export: one line, exit 2.
  execute_process(COMMAND "${RAYSPACE}" simulate "${WORK}/cornell" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "^rayspace: error: [^\n]*: not an export directory \\(no sequence.txt\\)\n$")
    set(failures "${failures}\nsimulate on a saved-calls directory: exit ${rc}: ${err}")
  endif()
elseif(PART STREQUAL "backend" OR PART STREQUAL "backend-faults" OR PART STREQUAL "backend-all" OR PART STREQUAL "schedules")
  # diff --backends emu,sim: every pass of the frame on the emulator and on the simulated GPU, bitwise.
  if(PART STREQUAL "backend")
    set(size 16x16)
    # The hierarchy pass by pass and fused, once under another schedule and subgroup size; the other
    # tracers (tl, the object tree, rah), sizes and schedules are the full tier's (backend-all, schedules).
    # The default path and the passes with the scan reduction under subgroup layouts other than
    # lavapipe's: narrower subgroups than advertised, lanes not in local order (docs/simulator.md); at
    # 8x8, since the layouts act within a workgroup (the full tier's backend-all runs them at 32x32).
    set(configs "crsh" "fused --path fused --schedule random:7 --subgroup-size 4" "partial --subgroup-layout partial:3 --size 8x8"
                "shuffled --subgroup-layout shuffled:3 --path passes --reduction scan --size 8x8")
    set(scenes cornell-mirrors)
  elseif(PART STREQUAL "backend-faults")
    set(configs "")  # the planted faults alone (below)
    set(scenes cornell-mirrors)
  elseif(PART STREQUAL "schedules")
    # The acceptance's product: 64x64, five schedules (a test each: SCHEDULE), four subgroup sizes.
    set(size 64x64)
    set(configs "")
    foreach(sg 4 8 32 64)
      list(APPEND configs "crsh --schedule ${SCHEDULE} --subgroup-size ${sg}")
    endforeach()
    set(scenes cornell-mirrors)
  else()
    set(size 32x32)
    # The grids' kernels are the simulator's slowest (a 16x16 frame takes about 50 s): at 16x16 only.
    set(configs "crsh" "crsh --path fused" "tl --algo tl" "tree --objects tree" "rah --algo rah" "quadtree --algo rah-quadtree"
                "crsh --subgroup-size 1" "crsh --subgroup-size 4" "crsh --subgroup-size 32" "crsh --subgroup-size 64"
                "grid --algo grid --size 16x16" "tl-partial --algo tl --subgroup-layout partial:5"
                "tree-shuffled --objects tree --subgroup-layout shuffled:5" "rah-partial --algo rah --subgroup-layout partial:6 --local-size 20"
                "partial-32 --subgroup-size 32 --local-size 12 --subgroup-layout partial:7"
                "grid-partial --algo grid --size 16x16 --subgroup-layout partial:8")
    set(scenes cornell-mirrors)
  endif()
  if(PART STREQUAL "backend-all")
    # office under the default configuration and pass by pass.
    list(APPEND configs "office-crsh --scene office" "office-fused --scene office --path fused")
  endif()
  foreach(scene ${scenes})
    foreach(config ${configs})
      separate_arguments(opts UNIX_COMMAND "${config}")
      list(POP_FRONT opts name)
      set(on "${scene}")
      list(FIND opts "--scene" at)
      if(at GREATER -1)
        math(EXPR next "${at} + 1")
        list(GET opts ${next} on)
        list(REMOVE_AT opts ${next} ${at})
      endif()
      set(sz --size ${size})
      if(config MATCHES "--size")
        set(sz "")
      endif()
      execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/${on}.json" ${sz} --backends emu,sim ${opts}
                      RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
      set(sg 8)
      if(config MATCHES "--subgroup-size ([0-9]+)")
        set(sg ${CMAKE_MATCH_1})
      endif()
      if(NOT rc EQUAL 0 OR NOT out MATCHES "on rayspace simulator \\(subgroup size ${sg}[,)]" OR NOT out MATCHES "comparison: bitwise"
         OR NOT out MATCHES "\n  all passes equal\n")
        set(failures "${failures}\ndiff ${on} --backends emu,sim ${config}: exit ${rc}: ${out}${err}")
      endif()
    endforeach()
  endforeach()
  if(PART STREQUAL "backend")
    # render --backend sim gives the emulator's digest (8x8: the diffs above compare every pass at 16x16).
    foreach(backend emu sim)
      execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 8x8 --no-oracle --backend ${backend}
                              --out "${WORK}/${backend}.png" --stats "${WORK}/${backend}.json"
                      RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
      if(NOT rc EQUAL 0)
        set(failures "${failures}\nrender --backend ${backend}: exit ${rc}: ${err}")
        set(digest_${backend} "none (${backend})")
      else()
        file(READ "${WORK}/${backend}.json" j)
        string(JSON digest_${backend} GET "${j}" digest)
      endif()
    endforeach()
    if(NOT digest_emu STREQUAL digest_sim)
      set(failures "${failures}\nrender --backend sim: digest ${digest_sim}, the emulator's ${digest_emu}")
    endif()
    # The simulated GPU's options belong to --backend sim: elsewhere refused with exit 2, naming them.
    foreach(bad "emu;--device-model;worst@--device-model worst: only the simulated GPU's arithmetic is chosen"
                "vulkan;--subgroup-layout;shuffled@--subgroup-layout shuffled: only the simulated GPU's subgroup layout is chosen"
                "emu;--sim-checks;none@--sim-checks none: only the simulated GPU runs these checkers"
                "vulkan;--subgroup-size;4@--subgroup-size 4: only the simulated GPU's subgroup size is chosen"
                "emu;--step-limit;1000@--step-limit 1000: only the simulated GPU has a step limit")
      string(REPLACE "@" ";" bad "${bad}")
      list(POP_BACK bad message)
      list(POP_FRONT bad backend)
      execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --no-oracle --backend ${backend} ${bad}
                              --out "${WORK}/refused.png" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
      if(NOT rc EQUAL 2 OR NOT err MATCHES "^rayspace: error: ${message}" OR EXISTS "${WORK}/refused.png")
        set(failures "${failures}\nrender --backend ${backend} ${bad}: exit ${rc}, expected 2 naming '${message}' and no image: ${err}")
      endif()
    endforeach()
    # Without a Vulkan driver, diff verifies the kernels on the simulated GPU.
    execute_process(COMMAND env VK_ICD_FILENAMES=${WORK}/none.json VK_DRIVER_FILES=${WORK}/none.json
                            "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --algo brute
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT err MATCHES "no Vulkan device: the kernels run on the simulated GPU \\(--backends emu,sim\\)"
       OR NOT out MATCHES "on rayspace simulator" OR NOT out MATCHES "\n  all passes equal\n")
      set(failures "${failures}\ndiff without a Vulkan driver: exit ${rc}, expected the simulated GPU: ${out}${err}")
    endif()
    # Any pair: the same kernels on the simulated GPU (expected) and on lavapipe are equal; a fault
    # planted with two devices as sides is refused (it would need a side chosen for it).
    execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 8x8 --backends sim,vulkan
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT out MATCHES "expected side: rayspace simulator \\(subgroup size 8\\), the same kernels"
       OR NOT out MATCHES "sim ms +vulkan ms" OR NOT out MATCHES "\n  all passes equal\n")
      set(failures "${failures}\ndiff --backends sim,vulkan: exit ${rc}, expected all passes equal with the simulator expected: ${out}${err}")
    endif()
    execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backends sim,vulkan --inject trim:1
                    RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
    if(NOT rc EQUAL 2 OR NOT err MATCHES "^rayspace: error: --inject with --backends sim,vulkan")
      set(failures "${failures}\ndiff --backends sim,vulkan --inject trim:1: exit ${rc}, expected 2: ${err}")
    endif()
    # The subgroup size is the simulated GPU's alone.
    execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backends emu,vulkan --subgroup-size 4
                    RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
    if(NOT rc EQUAL 2 OR NOT err MATCHES "^rayspace: error: --subgroup-size 4: only the simulated GPU's subgroup size is chosen")
      set(failures "${failures}\ndiff --backends emu,vulkan --subgroup-size 4: exit ${rc}, expected 2: ${err}")
    endif()
    # A planted fault in the kernel's arithmetic is a divergence; its impact runs the frame on the
    # simulated GPU as the actual side, and names it so (here that frame fails on the bad pairs).
    diff_with_report(reduce-fault "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backends emu,sim --inject reduce:1)
    set(actual "")
    if(j)
      string(JSON actual ERROR_VARIABLE jerr GET "${j}" impact actual)
    endif()
    if(NOT rc EQUAL 4 OR NOT err MATCHES "first divergent pass: reduce" OR NOT actual STREQUAL "sim"
       OR NOT err MATCHES "impact: not measured: the sim backend's frame failed")
      set(failures "${failures}\ndiff --backends emu,sim --inject reduce:1: exit ${rc}, expected 4 at reduce with the impact's actual side sim (got '${actual}'): ${err}")
    endif()
    # A workgroup past the step limit is the simulated GPU's fault, not a divergence: exit 7 naming the
    # pass, the pass reported failed (not equal), no verdict; render alike. At the default limit the
    # same frames are equal (above).
    diff_with_report(hang "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backends emu,sim --step-limit 1000)
    set(failed "")
    if(j)
      string(JSON fault_pass ERROR_VARIABLE jerr GET "${j}" backend_fault pass)
      string(JSON failed ERROR_VARIABLE jerr GET "${j}" passes 1 failed)
      string(JSON failed_equal ERROR_VARIABLE jerr GET "${j}" passes 1 equal)
    endif()
    if(NOT rc EQUAL 7 OR NOT err MATCHES "rayspace diff: the actual backend failed at pass surfaces; nothing was compared from there"
       OR NOT err MATCHES "workgroup \\(0, 0\\) ran more than 1000 lane-instructions: a hang" OR err MATCHES "divergent"
       OR NOT fault_pass STREQUAL "surfaces" OR NOT failed STREQUAL "ON" OR NOT failed_equal STREQUAL "OFF" OR out MATCHES "all passes equal")
      set(failures "${failures}\ndiff --step-limit 1000: exit ${rc}, expected 7 at surfaces reported failed (failed ${failed}): ${out}${err}")
    endif()
    execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --no-oracle --backend sim --step-limit 1000
                            --out "${WORK}/hang.png"
                    RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
    if(NOT rc EQUAL 7 OR NOT err MATCHES "^rayspace: backend failed: .*a hang" OR EXISTS "${WORK}/hang.png")
      set(failures "${failures}\nrender --backend sim --step-limit 1000: exit ${rc}, expected 7 and no image: ${err}")
    endif()
  endif()
  # The planted faults, on the kernel (backend-faults, default tier): each stops the diff with exit 6
  # naming its checker, those lavapipe runs benignly included (trim's divergent barrier, a dropped
  # barrier at local size 8, the global race, the load past the end, the undefined value). In
  # backend-all, with that checker off the same run must not name it: the checker, not another, is
  # what catches the fault (the default tier's "each finding names its checker, and with that checker
  # off ..." shows the same on small kernels).
  if(PART STREQUAL "backend-faults" OR PART STREQUAL "backend-all")
    set(all_checkers racecheck initcheck synccheck memcheck)
    # (trim runs in every frame: its faults take the host's brute tracer, which keeps the frames short.)
    foreach(fault "trim:divergent-barrier synccheck trim --algo brute" "trim:dropped-barrier racecheck trim --local-size 8 --algo brute"
                  "sort:dropped-barrier racecheck sort --local-size 8" "trim:shared-off-by-one initcheck trim --algo brute"
                  "reduce:subgroup-32 racecheck reduce" "trim:workgroup-offset memcheck trim --algo brute"
                  "trim:global-race racecheck trim --algo brute" "trim:out-of-bounds memcheck trim --algo brute"
                  "trim:undefined-value initcheck trim --algo brute")
      separate_arguments(f UNIX_COMMAND "${fault}")
      list(POP_FRONT f inject checker pass)
      set(others ${all_checkers})
      list(REMOVE_ITEM others ${checker})
      string(REPLACE ";" "," others "${others}")
      set(runs all)  # the default tier's part: caught by its checker
      if(PART STREQUAL "backend-all")
        set(runs ${others})  # the full tier's: not caught with that checker off
      endif()
      foreach(checks ${runs})
        execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backends emu,sim --inject ${inject}
                                ${f} --sim-checks ${checks} --no-impact --report "${WORK}/fault.json"
                        RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
        set(named "")
        if(EXISTS "${WORK}/fault.json")
          file(READ "${WORK}/fault.json" j)
          string(JSON named ERROR_VARIABLE jerr GET "${j}" simulator_checker checker)
          file(REMOVE "${WORK}/fault.json")
        endif()
        if(checks STREQUAL "all")
          if(NOT rc EQUAL 6 OR NOT err MATCHES "\n  ${checker} on the kernel of ${pass}: ${pass}[^\n]*: ${checker}: (invocation|an access)"
             OR NOT named STREQUAL checker)
            set(failures "${failures}\ndiff --backends emu,sim --inject ${fault}: exit ${rc}, expected 6 with ${checker} named: ${err}")
          endif()
        elseif(named STREQUAL checker OR err MATCHES "${checker} on the kernel")
          set(failures "${failures}\ndiff --backends emu,sim --inject ${fault} --sim-checks ${checks}: ${checker} named though off: ${err}")
        endif()
      endforeach()
    endforeach()
  endif()
elseif(PART STREQUAL "device-model")
  # The worst-conformant device: every loose float operation takes another permitted value. The
  # relaxed comparison accepts what it computes on the hierarchy's passes (exit 0, with differing
  # words counted within the spec); the bitwise one sees the first float pass diverge (exit 4); the
  # model is the simulated GPU's alone, and a malformed one is refused.
  set(cornell "${SRC}/scenes/cornell-mirrors.json")
  execute_process(COMMAND "${RAYSPACE}" diff "${cornell}" --size 16x16 --backends emu,sim --device-model worst:3 --report "${WORK}/worst.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "on rayspace simulator \\(subgroup size 8, worst:3 arithmetic\\)" OR NOT out MATCHES "comparison: relaxed"
     OR NOT out MATCHES "within the spec's precision: [0-9]+ call\\(s\\) differ only as a conformant device may"
     OR NOT out MATCHES "all passes equal or within the spec's precision")
    set(failures "${failures}\ndiff --device-model worst:3: exit ${rc}, expected 0 within the spec: ${out}${err}")
  endif()
  # The object tree's final tests have the intersect pass's model: their hits differ on this device
  # (two reflection calls) and are within the spec.
  execute_process(COMMAND "${RAYSPACE}" diff "${cornell}" --size 16x16 --backends emu,sim --device-model worst:3 --objects tree --no-impact
                          --report "${WORK}/tree-worst.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(tree_within 0)  # intersect.tree calls that differ and are within the spec
  if(EXISTS "${WORK}/tree-worst.json")
    file(READ "${WORK}/tree-worst.json" j)
    string(JSON calls LENGTH "${j}" calls)
    math(EXPR last "${calls} - 1")
    foreach(k RANGE ${last})
      string(JSON method GET "${j}" calls ${k} method)
      string(JSON within ERROR_VARIABLE none GET "${j}" calls ${k} within_spec)
      if(method STREQUAL "intersect.tree" AND within STREQUAL "ON")
        math(EXPR tree_within "${tree_within} + 1")
      endif()
    endforeach()
  endif()
  if(NOT rc EQUAL 0 OR NOT out MATCHES "all passes equal or within the spec's precision" OR NOT tree_within GREATER 0)
    set(failures "${failures}\ndiff --objects tree --device-model worst:3: exit ${rc}, expected 0 within the spec with intersect.tree run: ${out}${err}")
  endif()
  execute_process(COMMAND "${RAYSPACE}" diff "${cornell}" --size 16x16 --backends emu,sim --device-model worst:3 --compare bitwise --no-impact
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 4 OR NOT err MATCHES "first divergent pass: surfaces" OR NOT err MATCHES "emu 0x[0-9a-f]+ \\([^)]*\\), sim 0x")
    set(failures "${failures}\ndiff --device-model worst:3 --compare bitwise: exit ${rc}, expected 4 at surfaces: ${err}")
  endif()
  # --strict-math's claim: with + - * rounded to nearest, the strict kernels give the emulator's bits on
  # any conformant device; worst-nearest is that device with every other loose operation loose.
  execute_process(COMMAND "${RAYSPACE}" diff "${cornell}" --size 16x16 --backends emu,sim --device-model worst-nearest:5 --strict-math
                          --compare bitwise --no-impact
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "worst-nearest:5 arithmetic" OR NOT out MATCHES "\n  all passes equal\n")
    set(failures "${failures}\ndiff --device-model worst-nearest:5 --strict-math --compare bitwise: exit ${rc}, expected equal: ${out}${err}")
  endif()
  # Subgroup layouts Vulkan allows: every kernel hands out slots by rank, not local index, and counts
  # the subgroups launched (docs/simulator.md); trim with the planted linear-lanes fault assumes
  # linear lanes, which the shuffled layout catches and lavapipe's linear one runs benignly.
  foreach(layout "shuffled:1;0;;;" "partial:1;0;;;" "shuffled:1@trim;4;first divergent pass: trim;linear lanes;trim:linear-lanes"
                 "linear;0;not seen, the device executed it benignly;;trim:linear-lanes")
    list(GET layout 0 name)
    list(GET layout 1 want)
    list(GET layout 2 needle)
    list(GET layout 3 assumes)
    list(GET layout 4 fault)
    set(inject "")
    if(fault)
      set(inject --inject ${fault})
    endif()
    execute_process(COMMAND "${RAYSPACE}" diff "${cornell}" --size 16x16 --algo brute --backends emu,sim --subgroup-layout ${name} ${inject} --no-impact
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL want OR NOT "${out}${err}" MATCHES "${needle}" OR NOT out MATCHES "subgroup size 8"
       OR (assumes AND NOT err MATCHES "subgroup layout ${name}: a kernel that fails only under it assumes ${assumes}")
       OR (want EQUAL 0 AND NOT fault AND NOT out MATCHES "all passes equal"))
      set(failures "${failures}\ndiff --subgroup-layout ${name} ${inject}: exit ${rc}, expected ${want} (${needle}; assumes ${assumes}): ${out}${err}")
    endif()
  endforeach()
  # render --backend sim renders what the worst device computes: another digest than the emulator's,
  # the oracle still satisfied (the relaxed model holds on this scene); the emulator's with lavapipe's.
  foreach(model lavapipe worst)
    set(choice ${model})
    if(model STREQUAL "worst")
      set(choice worst:3)
    endif()
    execute_process(COMMAND "${RAYSPACE}" render "${cornell}" --size 16x16 --backend sim --device-model ${choice}
                            --out "${WORK}/render-${model}.png" --stats "${WORK}/render-${model}.json"
                    RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
    set(digest_${model} "none")
    set(device_${model} "none")
    if(NOT rc EQUAL 0)
      set(failures "${failures}\nrender --backend sim --device-model ${choice}: exit ${rc}, expected 0: ${err}")
    else()
      file(READ "${WORK}/render-${model}.json" j)
      string(JSON digest_${model} GET "${j}" digest)
      string(JSON device_${model} GET "${j}" backend device)
    endif()
  endforeach()
  execute_process(COMMAND "${RAYSPACE}" render "${cornell}" --size 16x16 --no-oracle --stats "${WORK}/render-emu.json" --out "${WORK}/render-emu.png"
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  set(digest_emu "none")
  if(rc EQUAL 0)
    file(READ "${WORK}/render-emu.json" j)
    string(JSON digest_emu GET "${j}" digest)
  endif()
  if(NOT digest_lavapipe STREQUAL digest_emu OR digest_worst STREQUAL digest_emu OR NOT device_worst MATCHES "worst:3 arithmetic")
    set(failures "${failures}\nrender --backend sim: lavapipe's model ${digest_lavapipe}, worst:3 ${digest_worst} (${device_worst}), "
                 "the emulator's ${digest_emu}: expected the first equal to it and the second not")
  endif()
  foreach(bad "--backends;emu,vulkan;--device-model;worst@only the simulated GPU's arithmetic is chosen"
              "--backends;emu,vulkan;--subgroup-layout;shuffled@only the simulated GPU's subgroup layout is chosen"
              "--backends;emu,sim;--subgroup-layout;partial:x@the seed 'x' is not an unsigned 64-bit integer"
              "--backends;emu,sim;--device-model;worst:x@the seed 'x' is not an unsigned 64-bit integer"
              "--backends;emu,sim;--device-model;nvidia@'nvidia' is not a device model")
    string(REPLACE "@" ";" bad "${bad}")
    list(POP_BACK bad message)
    execute_process(COMMAND "${RAYSPACE}" diff "${cornell}" --size 16x16 ${bad} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
    if(NOT rc EQUAL 2 OR NOT err MATCHES "${message}")
      set(failures "${failures}\ndiff ${bad}: exit ${rc}, expected 2 naming '${message}': ${err}")
    endif()
  endforeach()
elseif(PART STREQUAL "coverage-options")
  # diff --coverage-options: the lines a user's reduce kernel leaves unreached on a default frame are
  # reached with --reduction scan, but for the planted fault's branch, which no probe reaches.
  file(COPY "${SRC}/gpu/shaders/reduce.comp" DESTINATION "${WORK}/mine")
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backends emu,sim
                          --kernel reduce=${WORK}/mine/reduce.comp --coverage-options --report "${WORK}/options.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(probe "")
  set(never "")
  if(EXISTS "${WORK}/options.json")
    file(READ "${WORK}/options.json" j)
    string(JSON probe ERROR_VARIABLE jerr GET "${j}" coverage_options 0 probes 0 config)
    string(JSON never ERROR_VARIABLE jerr GET "${j}" coverage_options 0 unreached)
  endif()
  if(NOT rc EQUAL 0 OR NOT out MATCHES "\n    reached with --path passes --reduction scan: reduce.comp:" OR NOT probe STREQUAL "scan"
     OR NOT never MATCHES "^\\[ *\"workgroup.glsl:58\" *\\]$")
    set(failures "${failures}\ndiff --coverage-options: exit ${rc}, probe '${probe}', unreached '${never}': ${out}${err}")
  endif()
  # Nothing to probe without the simulated GPU or a user's kernel.
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backends emu,vulkan --coverage-options
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "--coverage-options: probes the lines of a --kernel")
    set(failures "${failures}\ndiff --coverage-options on Vulkan without a kernel: exit ${rc}, expected 2: ${err}")
  endif()
elseif(PART STREQUAL "walkthrough")
  # docs/simulator.md's walkthrough: a user's trim kernel whose copy of workgroup.glsl saves the
  # barrier after the scan reads the tile. lavapipe runs it benignly at local size 8 (all passes
  # equal); the simulator names the race on the user's own line.
  file(READ "${SRC}/gpu/shaders/workgroup.glsl" wg)
  string(REPLACE "  barrier();  // the tile is free for the next call" "  // (barrier saved)" mine "${wg}")
  if(mine STREQUAL wg)
    message(FATAL_ERROR "workgroup.glsl no longer has the barrier the walkthrough removes")
  endif()
  file(WRITE "${WORK}/mine/workgroup.glsl" "${mine}")
  file(COPY "${SRC}/gpu/shaders/trim.comp" DESTINATION "${WORK}/mine")
  set(walk diff "${SRC}/scenes/cornell-mirrors.json" --size 32x32 --algo brute --local-size 8 --kernel trim=${WORK}/mine/trim.comp --no-impact)
  execute_process(COMMAND "${RAYSPACE}" ${walk} --backends emu,vulkan RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "\n  all passes equal\n")
    set(failures "${failures}\nwalkthrough on lavapipe: exit ${rc}, expected all passes equal: ${out}${err}")
  endif()
  execute_process(COMMAND "${RAYSPACE}" ${walk} --backends emu,sim RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 6 OR NOT err MATCHES "racecheck on the kernel of trim: trim workgroup.glsl:[0-9]+: racecheck: invocation [0-9]+ writes shared word [0-9]+, which other invocations read with no barrier between \\(shared 'wg_tile'")
    set(failures "${failures}\nwalkthrough on the simulator: exit ${rc}, expected 6 with the race on wg_tile: ${out}${err}")
  endif()
  # With the barrier in place, the same run on the simulator is equal.
  file(WRITE "${WORK}/mine/workgroup.glsl" "${wg}")
  execute_process(COMMAND "${RAYSPACE}" ${walk} --backends emu,sim RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "\n  all passes equal\n")
    set(failures "${failures}\nwalkthrough with the barrier on the simulator: exit ${rc}, expected all passes equal: ${out}${err}")
  endif()
elseif(PART STREQUAL "all")
  foreach(scene cornell-mirrors office)
    save(${scene} ${scene} 32x32)
    foreach(call ${calls})
      export_call("${call}")
      if(out)
        simulate_equal("${out}")
      endif()
    endforeach()
  endforeach()
else()
  message(FATAL_ERROR "PART must be sample, all, backend, backend-faults, backend-all, schedules, device-model, walkthrough or coverage-options")
endif()
if(failures)
  message(FATAL_ERROR "cli_simulate:${failures}")
endif()
