# lavapipe at every subgroup width: LP_NATIVE_VECTOR_WIDTH=128, 256 and 512 give subgroups of 4, 8 and
# 16 lanes, and every pass diffs equal with the emulator taking the same size (the kernels assume no
# width). The subgroup size the diff reports proves the width took effect.
#   PART=sample (default tier)  widths 128 and 512 on cornell-mirrors at 32x32, local sizes 7, 32 and 256,
#                               the passes path at 128 and the object tree at 512
#   PART=all (full tier)        each width on cornell-mirrors, office and Sponza at 64x64, and cornell-mirrors
#                               at local sizes 1, 7, 32, 256 and 1024
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DDATA=<data root> -DPART=sample|all -P cli_widths.cmake
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
set(failures "")
if(PART STREQUAL "sample")
  set(runs "128|cornell-mirrors|32x32|--local-size 7" "512|cornell-mirrors|32x32|--local-size 32"
           "128|cornell-mirrors|32x32|--local-size 256 --path passes" "512|cornell-mirrors|32x32|--objects tree --local-size 12")
else()
  cli_require_data(cli.widths.all)
  set(runs "")
  foreach(width 128 256 512)
    foreach(scene cornell-mirrors office sponza)
      list(APPEND runs "${width}|${scene}|64x64|-")
    endforeach()
    foreach(local 1 7 32 256 1024)
      list(APPEND runs "${width}|cornell-mirrors|64x64|--local-size ${local}")
    endforeach()
  endforeach()
endif()
foreach(run IN LISTS runs)
  string(REPLACE "|" ";" fields "${run}")
  list(GET fields 0 width)
  list(GET fields 1 scene)
  list(GET fields 2 size)
  list(GET fields 3 extra)
  if(extra STREQUAL "-")  # no further options
    set(extra "")
  endif()
  separate_arguments(extra UNIX_COMMAND "${extra}")
  math(EXPR lanes "${width} / 32")
  set(ENV{LP_NATIVE_VECTOR_WIDTH} ${width})
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/${scene}.json" --data "${DATA}" --size ${size} --no-impact ${extra}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "on llvmpipe \\([^)]*${width} bits\\)" OR NOT out MATCHES "subgroup size ${lanes},"
     OR NOT out MATCHES "\n  all passes equal\n")
    string(APPEND failures "\nLP_NATIVE_VECTOR_WIDTH=${width} diff ${scene} ${size} ${extra}: exit ${rc}, expected equal at subgroup size ${lanes}: ${out}${err}")
  endif()
endforeach()
unset(ENV{LP_NATIVE_VECTOR_WIDTH})
if(failures)
  message(FATAL_ERROR "cli.widths:${failures}")
endif()
