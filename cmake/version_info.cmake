# Writes OUT (a header) with the version and the commit of the source tree, at every build, touching
# the file only when its contents change:
#   cmake -DSRC=<source dir> -DOUT=<header> -DVERSION=<x.y.z> -P version_info.cmake
set(commit "unknown (not a git checkout)")
find_package(Git QUIET)
if(GIT_FOUND AND EXISTS "${SRC}/.git")
  execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SRC}" rev-parse --short=12 HEAD
                  OUTPUT_VARIABLE hash OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc ERROR_QUIET)
  if(rc EQUAL 0)
    set(commit "${hash}")
    execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SRC}" status --porcelain --untracked-files=no
                    OUTPUT_VARIABLE dirty OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    if(NOT dirty STREQUAL "")
      set(commit "${commit} (with local changes)")
    endif()
  endif()
endif()
file(CONFIGURE OUTPUT "${OUT}" CONTENT "// Generated at build time by cmake/version_info.cmake.
#pragma once
#define RAYSPACE_VERSION \"${VERSION}\"
#define RAYSPACE_COMMIT \"${commit}\"
")
