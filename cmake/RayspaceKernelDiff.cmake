# rayspace_add_kernel_diff(NAME PASS KERNEL SCENE [SIZE WxH] [ALGO A] [BACKENDS B] [EXPECT equal|divergent]
#                          [ARGS ...]): registers a test of the calling project that diffs KERNEL, the
# project's own kernel for PASS, against rayspace's emulator on SCENE (a file, or the name of a bundled
# scene such as cornell-mirrors), pass by pass. The test passes when the verdict is EXPECT (default
# equal: every pass call bitwise equal); any other outcome fails it with the diff's first divergent
# pass or its error. The report is NAME.json in the current binary directory. ARGS go to
# `rayspace diff` as they are.
#
# Run as a script (-P), this file is the test's own driver.
if(CMAKE_SCRIPT_MODE_FILE AND DEFINED RAYSPACE_KERNEL_DIFF)
  string(REPLACE "|" ";" args "${ARGS}")
  execute_process(COMMAND "${RAYSPACE_KERNEL_DIFF}" diff ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}${err}")
  if(EXPECT STREQUAL "equal")
    set(want 0)
  else()
    set(want 4)  # rayspace diff's exit code for a divergent pass
  endif()
  if(NOT rc STREQUAL want)
    message(FATAL_ERROR "rayspace diff exited ${rc}; a verdict '${EXPECT}' exits ${want}")
  endif()
  return()
endif()

function(rayspace_add_kernel_diff)
  cmake_parse_arguments(PARSE_ARGV 0 D "" "NAME;PASS;KERNEL;SCENE;SIZE;ALGO;BACKENDS;EXPECT" "ARGS")
  foreach(required NAME PASS KERNEL SCENE)
    if(NOT D_${required})
      message(FATAL_ERROR "rayspace_add_kernel_diff: ${required} is required")
    endif()
  endforeach()
  if(D_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "rayspace_add_kernel_diff(${D_NAME}): unknown arguments ${D_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT D_EXPECT)
    set(D_EXPECT equal)
  endif()
  if(NOT D_EXPECT MATCHES "^(equal|divergent)$")
    message(FATAL_ERROR "rayspace_add_kernel_diff(${D_NAME}): EXPECT must be equal or divergent, not '${D_EXPECT}'")
  endif()
  get_filename_component(kernel "${D_KERNEL}" ABSOLUTE)
  if(NOT EXISTS "${kernel}")
    message(FATAL_ERROR "rayspace_add_kernel_diff(${D_NAME}): KERNEL '${D_KERNEL}' not found")
  endif()
  set(scene "${D_SCENE}")
  if(NOT EXISTS "${scene}" AND EXISTS "${rayspace_PREFIX}/share/rayspace/scenes/${D_SCENE}.json")
    set(scene "${rayspace_PREFIX}/share/rayspace/scenes/${D_SCENE}.json")
  elseif(NOT EXISTS "${scene}")
    message(FATAL_ERROR "rayspace_add_kernel_diff(${D_NAME}): SCENE '${D_SCENE}' is neither a file nor a bundled scene")
  endif()
  set(args "${scene}" --kernel "${D_PASS}=${kernel}" --report "${CMAKE_CURRENT_BINARY_DIR}/${D_NAME}.json")
  if(D_SIZE)
    list(APPEND args --size ${D_SIZE})
  endif()
  if(D_ALGO)
    list(APPEND args --algo ${D_ALGO})
  endif()
  if(D_BACKENDS)
    list(APPEND args --backends ${D_BACKENDS})
  endif()
  list(APPEND args ${D_ARGS})
  list(JOIN args "|" joined)
  add_test(NAME ${D_NAME}
           COMMAND ${CMAKE_COMMAND} "-DRAYSPACE_KERNEL_DIFF=$<TARGET_FILE:rayspace::rayspace>" "-DEXPECT=${D_EXPECT}" "-DARGS=${joined}"
                   -P "${CMAKE_CURRENT_FUNCTION_LIST_FILE}")
endfunction()
