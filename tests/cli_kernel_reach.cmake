# Where each compute pass runs, as a refused --kernel says (core pass_registry.h, kPassReach): for every
# pass with a compute kernel, a run with the host's brute tracer and the built-in kernel's source given as the
# user's either launches it (exit 0: a pass of every frame) or refuses it naming the options that run
# it and an example; the example run then launches it (exit 0; one run per example, with every kernel
# whose example it is). A pass refused without an example, or whose example does not launch it, fails.
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DSHADERS=<the kernels' .comp dir> -DWORK=<scratch> -P cli_kernel_reach.cmake
cmake_minimum_required(VERSION 3.19)
set(failures "")
# cornell-mirrors with a glass box: reflective and transparent materials.
file(MAKE_DIRECTORY "${WORK}")
file(READ "${SRC}/scenes/cornell-mirrors.json" cornell)
string(JSON glass SET "${cornell}" materials clay transparency 0.5)
string(JSON glass SET "${glass}" materials clay ior 1.5)
set(scene "${WORK}/glass.json")
file(WRITE "${scene}" "${glass}")
set(common render "${scene}" --backend vulkan --size 16x16 --no-oracle --out "${WORK}/frame.png")

# The passes, as the refusal of an unknown one lists them.
execute_process(COMMAND "${RAYSPACE}" render "${scene}" --backend vulkan --kernel none=x.spv RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT err MATCHES "passes with compute kernels: ([a-z., ]+)")
  message(FATAL_ERROR "no list of passes in: ${err}")
endif()
string(REPLACE ", " ";" passes "${CMAKE_MATCH_1}")
list(LENGTH passes n)
if(n LESS 25)
  message(FATAL_ERROR "only ${n} passes listed: ${passes}")
endif()

foreach(pass ${passes})
  # The kernel file: the pass's name with '_' for '.', but for the passes that share a kernel.
  string(REPLACE "." "_" kernel "${pass}")
  if(pass MATCHES "^(compress|decompress)$")
    set(kernel sort)
  elseif(pass MATCHES "^grid\\.(count|emit|cells)$")
    set(kernel grid_build)
  endif()
  set(k --kernel "${pass}=${SHADERS}/${kernel}.comp")
  execute_process(COMMAND "${RAYSPACE}" ${common} --algo brute ${k} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(rc EQUAL 0)
    continue()  # a pass of every frame
  endif()
  if(NOT rc EQUAL 2 OR NOT err MATCHES "never launched pass '${pass}' \\(it runs with [^;]+; for instance: render ([^)]*)\\)")
    set(failures "${failures}\n${pass}: with --algo brute: exit ${rc}, and no example that runs it: ${err}")
    continue()
  endif()
  # The example runs are grouped: one run per example with every kernel it should launch.
  string(MD5 key "${CMAKE_MATCH_1}")
  if(NOT DEFINED example_${key})
    set(example_${key} "${CMAKE_MATCH_1}")
    list(APPEND examples ${key})
  endif()
  list(APPEND kernels_${key} ${k})
  list(APPEND passes_${key} ${pass})
endforeach()
foreach(key ${examples})
  separate_arguments(example UNIX_COMMAND "${example_${key}}")
  execute_process(COMMAND "${RAYSPACE}" ${common} ${example} ${kernels_${key}} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    set(failures "${failures}\n${passes_${key}}: their example (${example}) does not launch them all: exit ${rc}: ${err}")
  endif()
endforeach()
if(failures)
  message(FATAL_ERROR "cli_kernel_reach:${failures}")
endif()
