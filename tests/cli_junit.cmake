# --junit FILE on diff and mutate: each report valid under docs/schemas/junit.xsd (xmllint), and its
# counts those of the run: an equal diff has no failure; a planted fault fails the calls of its pass,
# first in the pass that diverged; --inject-each gives a suite per fault; a mutate run has a case per
# mutant and per variant. The same path for --junit and --report is refused. (reproduce's relation
# checks: the doctest cases "junit: ..." and cli.reproduce.)
#   cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DXMLLINT=<xmllint> -DWORK=<scratch> -P cli_junit.cmake
cmake_minimum_required(VERSION 3.19)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(failures "")
set(scene "${SRC}/scenes/cornell-mirrors.json")

# junit(NAME RC COMMAND...): runs rayspace with --junit WORK/NAME.xml, expects exit RC and a valid
# file; sets `xml` in the caller.
function(junit name expect_rc)
  execute_process(COMMAND "${RAYSPACE}" ${ARGN} --junit "${WORK}/${name}.xml" RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err TIMEOUT 600)
  set(xml "" PARENT_SCOPE)
  if(NOT rc EQUAL expect_rc OR NOT EXISTS "${WORK}/${name}.xml")
    set(failures "${failures}\n${name}: exit ${rc} (expected ${expect_rc}) or no JUnit file: ${out}${err}" PARENT_SCOPE)
    return()
  endif()
  execute_process(COMMAND "${XMLLINT}" --noout --schema "${SRC}/docs/schemas/junit.xsd" "${WORK}/${name}.xml"
                  RESULT_VARIABLE valid ERROR_VARIABLE why)
  if(NOT valid EQUAL 0)
    set(failures "${failures}\n${name}: not valid under junit.xsd: ${why}" PARENT_SCOPE)
  endif()
  file(READ "${WORK}/${name}.xml" x)
  set(xml "${x}" PARENT_SCOPE)
endfunction()

# expect(NAME REGEX): the last file matches REGEX.
function(expect name regex)
  if(NOT xml MATCHES "${regex}")
    set(failures "${failures}\n${name}: the JUnit file does not match '${regex}':\n${xml}" PARENT_SCOPE)
  endif()
endfunction()

junit(diff_equal 0 diff "${scene}" --size 24x24)
expect(diff_equal "<testsuites name=\"rayspace diff\" tests=\"[1-9][0-9]*\" failures=\"0\" errors=\"0\"")
expect(diff_equal "classname=\"diff.reduce\"")

junit(diff_fault 4 diff "${scene}" --size 24x24 --inject reduce --no-impact)
expect(diff_fault "<testsuites name=\"rayspace diff\" tests=\"[1-9][0-9]*\" failures=\"[1-9]")
string(REGEX MATCH "<testcase classname=\"([a-z.]+)\" name=\"[^\"]*\" time=\"[0-9.]+\">\n +<failure" first "${xml}")
if(NOT CMAKE_MATCH_1 STREQUAL "diff.reduce")
  string(APPEND failures "\ndiff_fault: the first failed case is '${CMAKE_MATCH_1}', expected diff.reduce")
endif()
expect(diff_fault "<failure type=\"divergence\" message=\"pairs\\[[0-9]+\\]: expected ")

junit(diff_each 4 diff "${scene}" --size 24x24 --inject-each reduce,trim --no-impact)
string(REGEX MATCHALL "<testsuite name=\"diff [^\"]* --inject (reduce|trim)\"" suites "${xml}")
list(LENGTH suites n)
if(NOT n EQUAL 2)
  string(APPEND failures "\ndiff_each: ${n} suites, expected one per fault (2)")
endif()

junit(mutate 0 mutate "${scene}" --config crsh --size 16x16 --limit 1 --variants 1 --timeout 60 --pass trim)
expect(mutate "<testsuite name=\"mutate on vulkan\" tests=\"1\"")
expect(mutate "<testsuite name=\"mutate variants\" tests=\"1\"")
expect(mutate "classname=\"mutate.trim.comp\" name=\"trim.comp:")

execute_process(COMMAND "${RAYSPACE}" diff "${scene}" --size 8x8 --report "${WORK}/same.xml" --junit "${WORK}/same.xml"
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--junit '.*same.xml': the same file as --report")
  string(APPEND failures "\nsame file: exit ${rc}, stderr '${err}'")
endif()

if(failures)
  message(FATAL_ERROR "cli.junit:${failures}")
endif()
message(STATUS "cli.junit: diff (equal, a planted fault, --inject-each) and mutate reports valid and counted")
