# `rayspace --version`: exit 0, and on stdout the version, the commit (or why there is none), the
# backends built in and the libraries, run as
#   cmake -DRAYSPACE=<exe> -DVULKAN=ON|OFF -P cli_version.cmake
execute_process(COMMAND "${RAYSPACE}" --version RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "rayspace --version: exit ${rc}: ${err}")
endif()
set(needles "rayspace [0-9]+\\.[0-9]+\\.[0-9]+\n" "commit ([0-9a-f]+|unknown)" "backends: emu"
            "Embree [0-9]" "CGAL [0-9]" "OpenImageIO [0-9]" "libpng [0-9]" "compiler: ")
if(VULKAN)
  list(APPEND needles "backends: emu, vulkan")
endif()
foreach(n IN LISTS needles)
  if(NOT out MATCHES "${n}")
    message(FATAL_ERROR "rayspace --version does not say '${n}':\n${out}")
  endif()
endforeach()
if(NOT err STREQUAL "")
  message(FATAL_ERROR "rayspace --version wrote to stderr: ${err}")
endif()
message(STATUS "${out}")
