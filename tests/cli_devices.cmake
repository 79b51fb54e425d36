# `rayspace devices` lists every requirement as met on this machine's device, and each requirement
# faked as missing (--device-lacks) is refused by name: by `devices` (NOT MET, exit 2) and by a
# Vulkan render (exit 2, one line naming it); an optional one (absent) only by the passes that need it:
# the grids' 64-bit floats, and each subgroup feature the kernels' SPIR-V declares.
# --local-size beyond a faked workgroup limit is refused too.
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -P cli_devices.cmake
set(failures "")
execute_process(COMMAND "${RAYSPACE}" devices RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "usable" OR out MATCHES "NOT MET")
  message(FATAL_ERROR "rayspace devices: exit ${rc}, expected 0 with every requirement met:\n${out}${err}")
endif()
# The requirement names: the word after "met" on each requirement line.
string(REGEX MATCHALL "\n    met +[^ ]+" lines "${out}")
set(names "")
foreach(line IN LISTS lines)
  string(REGEX REPLACE "\n    met +" "" name "${line}")
  list(APPEND names "${name}")
endforeach()
list(REMOVE_DUPLICATES names)
list(LENGTH names count)
set(optional 0)
set(subgroup_rows 0)
if(count LESS 12)
  message(FATAL_ERROR "rayspace devices lists ${count} requirements, expected at least 12:\n${out}")
endif()
foreach(name IN LISTS names)
  execute_process(COMMAND "${RAYSPACE}" devices --device-lacks "${name}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(REPLACE "[" "\\[" pattern "${name}")
  string(REPLACE "]" "\\]" pattern "${pattern}")
  if(out MATCHES "absent +${pattern} " AND name MATCHES "^VK_SUBGROUP_FEATURE_")
    # A subgroup feature the kernels' SPIR-V declares: the device stays usable, a kernel declaring it
    # is refused at creation naming it; without VOTE the passes path (no traverse.compact) renders.
    math(EXPR subgroup_rows "${subgroup_rows} + 1")
    if(NOT rc EQUAL 0 OR NOT out MATCHES "usable")
      string(APPEND failures "\ndevices --device-lacks ${name} (optional): exit ${rc}, expected 0 and usable")
    endif()
    execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backend vulkan --no-oracle
                            --device-lacks "${name}" --out "${WORK}/x.png" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 2 OR NOT err MATCHES "kernel [a-z_.]+ declares subgroup operations '[^']+' lacks in compute: [A-Z_, ]*${pattern}")
      string(APPEND failures "\nrender --device-lacks ${name}: exit ${rc}, expected 2 naming the kernel and ${name}: ${err}")
    endif()
    if(name STREQUAL "VK_SUBGROUP_FEATURE_VOTE_BIT")
      execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backend vulkan --no-oracle
                              --path passes --device-lacks "${name}" --out "${WORK}/x.png" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
      if(NOT rc EQUAL 0)
        string(APPEND failures "\nrender --path passes --device-lacks ${name}: exit ${rc}, expected 0: ${err}")
      endif()
    endif()
    continue()
  endif()
  if(out MATCHES "absent +${pattern} ")
    # An optional requirement (the grids' build needs 64-bit floats): the device stays usable, every
    # other pass renders, and --algo grid on it is refused naming what it lacks.
    math(EXPR optional "${optional} + 1")
    if(NOT rc EQUAL 0 OR NOT out MATCHES "usable")
      string(APPEND failures "\ndevices --device-lacks ${name} (optional): exit ${rc}, expected 0 and usable")
    endif()
    execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backend vulkan --no-oracle
                            --device-lacks "${name}" --out "${WORK}/x.png" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      string(APPEND failures "\nrender --device-lacks ${name} (optional): exit ${rc}, expected 0: ${err}")
    endif()
    execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backend vulkan --algo grid
                            --device-lacks "${name}" --out "${WORK}/x.png" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 2 OR NOT err MATCHES "--algo grid: the Vulkan device .* lacks shaderFloat64 or shaderSignedZeroInfNanPreserveFloat64")
      string(APPEND failures "\nrender --algo grid --device-lacks ${name}: exit ${rc}, expected 2 naming it: ${err}")
    endif()
    continue()
  endif()
  if(NOT rc EQUAL 2 OR NOT out MATCHES "NOT MET +${pattern} ")
    string(APPEND failures "\ndevices --device-lacks ${name}: exit ${rc}, expected 2 and '${name}' NOT MET")
  endif()
  execute_process(COMMAND "${RAYSPACE}" render "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --backend vulkan
                          --device-lacks "${name}" --out "${WORK}/x.png"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(FIND "${err}" "lacks what rayspace needs: ${name} (" at)
  if(NOT rc EQUAL 2 OR at EQUAL -1)
    string(APPEND failures "\nrender --device-lacks ${name}: exit ${rc}, expected 2 naming it: ${err}")
  endif()
endforeach()
execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 16x16 --local-size 64
                        --device-lacks maxComputeWorkGroupInvocations=32
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--local-size 64: .* allows at most 32 invocations per workgroup")
  string(APPEND failures "\ndiff --local-size 64 on a device allowing 32: exit ${rc}: ${err}")
endif()
execute_process(COMMAND "${RAYSPACE}" devices --device-lacks bogus RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--device-lacks 'bogus': not a requirement")
  string(APPEND failures "\ndevices --device-lacks bogus: exit ${rc}: ${err}")
endif()
# The kernels declare basic, vote, arithmetic, ballot and shuffle (traverse.compact all five).
if(NOT subgroup_rows EQUAL 5)
  string(APPEND failures "\n${subgroup_rows} subgroup feature rows, expected 5 (basic, vote, arithmetic, ballot, shuffle)")
endif()
if(NOT optional EQUAL 2)
  string(APPEND failures "\n${optional} optional requirements, expected 2 (shaderFloat64 and its SignedZeroInfNanPreserve)")
endif()
if(failures)
  message(FATAL_ERROR "cli.devices:${failures}")
endif()
message(STATUS "cli.devices: ${count} requirements met, each refused by name when faked missing")
