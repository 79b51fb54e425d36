# Guard words after every mappable storage buffer (docs/gpu.md, "Guard words"): a kernel that writes
# one element past its output, or reads one past its input, is a divergence of its pass (exit 4),
# though every compared element is equal; the unmodified kernels diff equal.
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch> -P cli_guard.cmake
set(failures "")
file(MAKE_DIRECTORY "${WORK}")
# guard_case(NAME KERNEL PASS FROM TO NEEDLE): the kernel with FROM replaced by TO, diffed at 48x47
# (pixel and ray counts no multiple of the local size, so an invocation past the end exists).
function(guard_case name kernel pass from to needle)
  file(READ "${SRC}/gpu/shaders/${kernel}.comp" text)
  string(FIND "${text}" "${from}" at)
  if(at EQUAL -1)
    set(failures "${failures}\n${name}: '${from}' not found in ${kernel}.comp" PARENT_SCOPE)
    return()
  endif()
  string(REPLACE "${from}" "${to}" text "${text}")
  file(WRITE "${WORK}/${name}.comp" "${text}")
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 48x47 --kernel "${pass}=${WORK}/${name}.comp"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 4 OR NOT "${out}${err}" MATCHES "first divergent pass: ${pass}\n" OR NOT "${out}${err}" MATCHES "${needle}")
    set(failures "${failures}\n${name}: exit ${rc}, expected 4 in ${pass} matching '${needle}':\n${out}${err}" PARENT_SCOPE)
  endif()
endfunction()
# One pixel past the surfaces' output: the guard word after it is overwritten.
guard_case(write surfaces surfaces "if (i >= pc.pixels) return;" "if (i > pc.pixels) return;"
           "kernel surfaces wrote past the end of binding [0-9]+")
# A kernel that depends on the word one surface past the end: robust access would give it zero (and
# the emulator's answer), the guard word does not.
guard_case(read raygen_shadow raygen.shadow "const Surface sf = surfaces[s];"
           "Surface sf = surfaces[s]; if (floatBitsToUint(surfaces[pc.surface_count].position.x) != 0u) sf.position.x += 1.0;"
           "raygen.shadow/rays: [0-9]+ of")
execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 48x47 RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "all passes equal")
  set(failures "${failures}\nclean: exit ${rc}: ${out}${err}")
endif()
if(failures)
  message(FATAL_ERROR "cli.guard:${failures}")
endif()
message(STATUS "cli.guard: a write and a read past an array's end caught in their pass; the clean diff equal")
