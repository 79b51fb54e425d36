# A frame whose per-pixel and per-ray buffers exceed one storage binding of the device itself (no
# test hook): the Vulkan backend must run it in parts and pages and still give the emulator's digest
# and PNG bytes. cornell-mirrors at 2048x1152: 80-byte surfaces take 188,743,680 bytes and 64-byte
# shadow rays 150,994,944, both above lavapipe's 134,217,728.
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DDATA=<data root> -DWORK=<scratch> -P cli_large_frame.cmake
set(failures "")
file(MAKE_DIRECTORY "${WORK}")
include("${CMAKE_CURRENT_LIST_DIR}/cli_same_frame.cmake")

set(width 2048)
set(height 1152)
same_frame(cornell_large "${SRC}/scenes/cornell-mirrors.json" ${width}x${height})
if(NOT failures)
  file(READ "${WORK}/cornell_large_vulkan.json" j)
  string(JSON binding GET "${j}" backend binding_bytes)
  string(JSON splits GET "${j}" backend split_dispatches)
  string(JSON paged GET "${j}" backend paged_arrays)
  math(EXPR surface_bytes "${width} * ${height} * 80")
  math(EXPR ray_bytes "${width} * ${height} * 64")
  message(STATUS "binding ${binding} bytes: surfaces ${surface_bytes}, rays ${ray_bytes}; ${splits} split dispatches, ${paged} paged arrays")
  if(surface_bytes GREATER binding AND splits LESS 1)
    set(failures "${failures}\nsurfaces exceed one binding but no pass ran in parts")
  endif()
  if(ray_bytes GREATER binding AND paged LESS 1)
    set(failures "${failures}\nrays exceed one binding but no array was paged")
  endif()
endif()

if(failures)
  message(FATAL_ERROR "large frame:${failures}")
endif()
