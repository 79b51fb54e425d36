# An installed rayspace in another project's build: `cmake --install` of this build to a prefix
# outside the source and build trees (MODE=deb: the Debian packages `cpack -G DEB` makes, resolved by
# `apt-get install --simulate` and unpacked there with `dpkg-deb -x`), tests/consumer/ configured against it with find_package(rayspace)
# and built, and its tests run with the source and build trees hidden (a private mount namespace
# with empty file systems over both): the installed command and the consumer's use of the library
# API and of rayspace_add_kernel_diff() must work from the install alone. The consumer's tests:
# `api`, `helper.copy` and `helper.planted` must pass; `helper.planted_as_equal` (its planted bug
# registered as equal) must fail.
#   cmake -DBUILD=<build dir> -DSRC=<source dir> [-DMODE=install|deb] -P install_consumer.cmake
cmake_minimum_required(VERSION 3.25)
set(tmp "$ENV{TMPDIR}")
if(NOT tmp)
  set(tmp /tmp)
endif()
string(RANDOM LENGTH 8 tag)
set(work "${tmp}/rayspace-install-test-${tag}")
set(prefix "${work}/prefix")
set(failures "")
if(NOT MODE)
  set(MODE install)
endif()

if(MODE STREQUAL "deb")
  include("${CMAKE_CURRENT_LIST_DIR}/install_deb.cmake")  # sets prefix, or fails
else()
  execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD}" --prefix "${prefix}" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    file(REMOVE_RECURSE "${work}")
    message(FATAL_ERROR "cmake --install failed (${rc}): ${err}")
  endif()
endif()
foreach(f bin/rayspace lib/cmake/rayspace/rayspaceConfig.cmake lib/cmake/rayspace/RayspaceKernelDiff.cmake include/rayspace/api.h
          include/rayspace/layout.h share/rayspace/shaders/reduce.comp share/rayspace/shaders/workgroup.glsl
          share/rayspace/scenes/cornell-mirrors.json lib/rayspace/librayspace_image_oiio.so)
  if(NOT EXISTS "${prefix}/${f}")
    string(APPEND failures "\ninstall lacks ${f}")
  endif()
endforeach()
# The package's text files name no path of the tree it was built in.
file(GLOB_RECURSE texts "${prefix}/lib/cmake/*" "${prefix}/include/*")
foreach(f ${texts})
  file(STRINGS "${f}" hits REGEX "${SRC}|${BUILD}")
  if(hits)
    string(APPEND failures "\n${f} names the build's tree: ${hits}")
  endif()
endforeach()

execute_process(COMMAND ${CMAKE_COMMAND} -S "${SRC}/tests/consumer" -B "${work}/consumer" -G Ninja "-DCMAKE_PREFIX_PATH=${prefix}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
  execute_process(COMMAND ${CMAKE_COMMAND} --build "${work}/consumer" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
endif()
if(NOT rc EQUAL 0)
  file(REMOVE_RECURSE "${work}")
  message(FATAL_ERROR "the consumer project does not configure or build against the install: ${out}${err}")
endif()

# The trees hidden: tmpfs over the source tree, and over the build tree when it lies elsewhere.
set(hide "mount -t tmpfs none '${SRC}'")
string(FIND "${BUILD}/" "${SRC}/" inside)
if(NOT inside EQUAL 0)
  string(APPEND hide " && mount -t tmpfs none '${BUILD}'")
endif()
# lavapipe's shader cache moves out of the hidden build tree.
set(run "${hide} && test ! -e '${SRC}/CMakeLists.txt' && export MESA_SHADER_CACHE_DIR='${work}/mesa-cache' && '${prefix}/bin/rayspace' --version && ctest --test-dir '${work}/consumer' --output-on-failure")
execute_process(COMMAND unshare --mount sh -c "${run}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(out MATCHES "Total Test time")
  foreach(t api helper.copy helper.planted)
    if(NOT out MATCHES "Test +#[0-9]+: ${t} [.]+ +Passed")
      string(APPEND failures "\nconsumer test ${t} did not pass")
    endif()
  endforeach()
  if(NOT out MATCHES "Test +#[0-9]+: helper.planted_as_equal [.]+[*]+Failed")
    string(APPEND failures "\nconsumer test helper.planted_as_equal (a planted bug registered as equal) did not fail")
  endif()
  if(NOT out MATCHES "rayspace [0-9]+[.][0-9]+[.][0-9]+\ncommit")
    string(APPEND failures "\nthe installed rayspace --version printed no version")
  endif()
else()
  string(APPEND failures "\ncould not run the consumer's tests with the trees hidden (unshare --mount, as root): exit ${rc}")
endif()
file(REMOVE_RECURSE "${work}")
if(failures)
  message(FATAL_ERROR "install.consumer:${failures}")
endif()
message("install.consumer (${MODE}): the installed package works with the source and build trees hidden")
