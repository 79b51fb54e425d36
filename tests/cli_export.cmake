# `rayspace export`: a call saved by `diff --save-inputs` as a reproducer that runs without rayspace.
# Each case saves the calls of a small diff, exports some, builds the exported repro.c with the C
# compiler against the Vulkan loader and runs it on the device (with the validation layer):
#   clean.<variant>    one call of every pass method and place in the frame of a clean diff: every
#                      reproducer says "equal" (exit 0) and the raster is refused by name (exit 2)
#   fault.<pass>:<n>   the first divergent call of a diff with --inject: its reproducer runs the
#                      faulted kernel and reports the first mismatch (exit 1)
#   inject             calls of a clean diff exported with --inject PASS:N: each reports a mismatch
#   validate           the reproducer's --validate and REPRO_VALIDATE=1 load the validation layer
# tests/CMakeLists.txt includes this file with CASE unset to collect the case names; each test runs
#   cmake -DRAYSPACE=<exe> -DCC=<C compiler> -DSRC=<source dir> -DWORK=<scratch> -DCASE=<case> -P cli_export.cmake
set(cli_export_cases "")
set(matched FALSE)
if(DEFINED CASE)
  string(REPLACE ":" "_" case_dir "${CASE}")
  set(case_work "${WORK}/${case_dir}")  # per case: cases run in parallel
  file(REMOVE_RECURSE "${case_work}")
  file(MAKE_DIRECTORY "${case_work}")
endif()

# The start of a case function: records `name` and returns unless it is the case to run.
macro(begin_case name)
  list(APPEND cli_export_cases "${name}")
  set(cli_export_cases "${cli_export_cases}" PARENT_SCOPE)
  if(NOT DEFINED CASE OR NOT "${CASE}" STREQUAL "${name}")
    return()
  endif()
  set(matched TRUE PARENT_SCOPE)
endmacro()

# Failures gather in a global property, so that helpers at any depth can add to them.
function(fail message)
  set_property(GLOBAL APPEND_STRING PROPERTY cli_export_failures "\n${CASE}: ${message}")
endfunction()

# The --split-bytes and --max-groups among the diff options, which the export must repeat.
function(limit_args out)
  set(limits "")
  set(args ${ARGN})
  list(LENGTH args n)
  foreach(i RANGE ${n})
    if(i LESS n)
      list(GET args ${i} a)
      if(a STREQUAL "--split-bytes" OR a STREQUAL "--max-groups")
        math(EXPR j "${i} + 1")
        list(GET args ${j} v)
        list(APPEND limits ${a} ${v})
      endif()
    endif()
  endforeach()
  set(${out} "${limits}" PARENT_SCOPE)
endfunction()

# Saves every call of a 64x64 cornell-mirrors diff (with the given diff options) under case_work/saved.
function(save_calls expect_rc)
  execute_process(COMMAND "${RAYSPACE}" diff "${SRC}/scenes/cornell-mirrors.json" --size 64x64
                          --save-inputs "${case_work}/saved" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL expect_rc)
    fail("diff ${ARGN}: exit ${rc}, expected ${expect_rc}: ${out}${err}")
  endif()
endfunction()

# Exports DIR into OUT; sets export_rc, export_out (stdout and stderr).
function(export_call dir out)
  execute_process(COMMAND "${RAYSPACE}" export "${dir}" --out "${out}" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE o ERROR_VARIABLE e)
  set(export_rc "${rc}" PARENT_SCOPE)
  set(export_out "${o}${e}" PARENT_SCOPE)
endfunction()

# Builds OUT/repro.c into case_work/repro with the strictest warnings (C99, one file, -lvulkan).
function(build_repro out)
  foreach(f repro.c README.md sequence.txt call.json)
    if(NOT EXISTS "${out}/${f}")
      fail("the export ${out} has no ${f}")
    endif()
  endforeach()
  execute_process(COMMAND "${CC}" -std=c99 -Wall -Wextra -pedantic -Werror "${out}/repro.c" -lvulkan -o "${case_work}/repro"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE o ERROR_VARIABLE e)
  if(NOT rc EQUAL 0)
    fail("cc repro.c -lvulkan: exit ${rc}: ${o}${e}")
  endif()
endfunction()

# Runs the built reproducer on OUT under the validation layer: exit EXPECT_RC, stdout matching
# EXPECT_TEXT, and no validation message.
function(run_repro out expect_rc expect_text)
  execute_process(COMMAND "${case_work}/repro" "${out}" --validate RESULT_VARIABLE rc OUTPUT_VARIABLE o ERROR_VARIABLE e)
  if(NOT rc EQUAL expect_rc OR NOT o MATCHES "${expect_text}" OR "${o}${e}" MATCHES "validation:")
    fail("repro ${out}: exit ${rc} (expected ${expect_rc}, '${expect_text}'): ${o}${e}")
  endif()
endfunction()

# The saved calls whose pass method matches METHODS, the first of each method and ray kind: one call
# of each kind the frame makes.
function(distinct_calls out methods)
  file(GLOB dirs LIST_DIRECTORIES true "${case_work}/saved/*")
  list(SORT dirs)
  set(seen "")
  set(picked "")
  foreach(d IN LISTS dirs)
    file(READ "${d}/pass.json" pj)
    string(JSON method GET "${pj}" method)
    get_filename_component(label "${d}" NAME)
    string(REGEX MATCH "shadow|reflection|refraction" kind "${label}")
    list(FIND seen "${method}|${kind}" at)
    if(at EQUAL -1 AND method MATCHES "${methods}")
      list(APPEND seen "${method}|${kind}")
      list(APPEND picked "${d}")
    endif()
  endforeach()
  set(${out} "${picked}" PARENT_SCOPE)
endfunction()

# clean_case(NAME METHODS [diff options]): every distinct call of a clean diff whose method matches
# METHODS exports and replays equal; the raster is refused, naming the pass and leaving nothing behind.
function(clean_case name methods)
  begin_case("${name}")
  save_calls(0 ${ARGN})
  distinct_calls(calls "${methods}")
  list(LENGTH calls n)
  set(built FALSE)
  limit_args(limits ${ARGN})
  foreach(d IN LISTS calls)
    get_filename_component(call "${d}" NAME)
    export_call("${d}" "${case_work}/export/${call}" ${limits})
    if(call MATCHES "-raster$")
      if(NOT export_rc EQUAL 2 OR NOT export_out MATCHES "pass raster cannot be exported: it draws with a graphics pipeline"
         OR EXISTS "${case_work}/export/${call}")
        fail("export ${call}: exit ${export_rc}, expected 2 naming the raster and nothing written: ${export_out}")
      endif()
      continue()
    endif()
    if(NOT export_rc EQUAL 0)
      fail("export ${call}: exit ${export_rc}: ${export_out}")
      continue()
    endif()
    if(NOT built)
      build_repro("${case_work}/export/${call}")
      set(built TRUE)
    endif()
    run_repro("${case_work}/export/${call}" 0 "\nequal: [0-9]+ read-back")
  endforeach()
  file(GLOB partial "${case_work}/export/*.partial-*")
  if(partial)
    fail("partial exports left behind: ${partial}")
  endif()
  message(STATUS "${name}: ${n} distinct calls exported and replayed")
endfunction()

# The first call whose recorded comparison diverged (or fails).
function(first_divergent out)
  file(GLOB dirs LIST_DIRECTORIES true "${case_work}/saved/*")
  list(SORT dirs)
  foreach(d IN LISTS dirs)
    file(READ "${d}/comparison.json" cj)
    string(JSON equal GET "${cj}" equal)
    if(NOT equal)
      set(${out} "${d}" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  set(${out} "" PARENT_SCOPE)
endfunction()

# fault_case(NAME INJECT PASS [diff and export options]): the first divergent call of a diff with the
# planted fault, exported as recorded (no --inject): the fault is set in the exported pipeline of
# PASS and the reproducer reports the first mismatch.
function(fault_case name inject pass)
  begin_case("${name}")
  save_calls(4 --inject ${inject} ${ARGN})
  first_divergent(d)
  if(NOT d)
    fail("no saved call diverged")
    return()
  endif()
  string(REGEX REPLACE "^[^:]*:" "" number "${inject}")
  limit_args(limits ${ARGN})
  export_call("${d}" "${case_work}/export" ${limits})
  file(STRINGS "${case_work}/export/sequence.txt" pipelines REGEX "^pipeline [0-9]+ ${pass} ")
  if(NOT export_rc EQUAL 0 OR NOT export_out MATCHES "kernels: [^\n]*${pass} \\(planted fault ${number}\\)"
     OR NOT pipelines MATCHES "^pipeline [0-9]+ ${pass} kernels/${pass}.spv [0-9]+ ${number} ")
    fail("export ${d}: exit ${export_rc}, expected the fault in ${pass}'s pipeline: ${export_out} ${pipelines}")
    return()
  endif()
  build_repro("${case_work}/export")
  run_repro("${case_work}/export" 1 "\nfirst mismatch: read-back [0-9]+, buffer '[^']+' \\([0-9]+ bytes\\), [^\n]*: expected 0x[0-9a-f]+ \\([^)]*\\) got 0x[0-9a-f]+ \\([^)]*\\)\nmismatch: ")
endfunction()

clean_case(clean.passes ".")
clean_case(clean.fused "^traverse[.]compact" --path fused)
clean_case(clean.tree "^(tree[.]|intersect[.]tree)" --objects tree)
clean_case(clean.quadtree-scan "^(hash|reduce|traverse[.])" --algo rah-quadtree --reduction scan)
# Binding limits that split, page and fold into rows: the export records with the same limits.
clean_case(clean.paged "." --split-bytes 65536 --max-groups 2)

fault_case(fault.trim:1 trim:1 trim)
fault_case(fault.sort:1 sort:1 sort)
fault_case(fault.traverse:1 traverse:1 traverse)
fault_case(fault.intersect:1 intersect:1 intersect)
fault_case(fault.fused.traverse.compact:2 traverse.compact:2 traverse.compact --path fused)
# Faults that show only on split dispatches and paged bindings: the carry between trim's parts, and
# every paged load reading the first page.
fault_case(fault.paged.trim:2 trim:2 trim --split-bytes 65536)
fault_case(fault.paged.intersect:2 intersect:2 intersect --split-bytes 65536)

# Calls of a clean diff exported with a fault of their own pass (`export --inject`): every pass's
# reproducer sees it.
function(inject_case name)
  begin_case("${name}")
  save_calls(0)
  set(built FALSE)
  foreach(pair surfaces.b0=surfaces:1 raygen.shadow.b0=raygen.shadow:2 raygen.reflection.b1=raygen.reflection:1
               hash.shadow.b0=hash:1 compress.shadow.b0=compress:1 decompress.shadow.b0=decompress:1
               build.shadow.b0=build:1 traverse.L2.shadow.b0=traverse:1 reduce.L2.shadow.b0=reduce:1
               intersect.reflection.b1=intersect:1 surfaces.reflection.b1=surfaces.hits:1 shade.b0=shade:1 resolve=resolve:1)
    string(REPLACE "=" ";" pair "${pair}")
    list(GET pair 0 label)
    list(GET pair 1 inject)
    file(GLOB d LIST_DIRECTORIES true "${case_work}/saved/*-${label}")
    list(GET d 0 d)
    export_call("${d}" "${case_work}/export/${inject}" --inject ${inject})
    if(NOT export_rc EQUAL 0 OR NOT export_out MATCHES "\\(planted fault ")
      fail("export ${label} --inject ${inject}: exit ${export_rc}: ${export_out}")
      continue()
    endif()
    if(NOT built)
      build_repro("${case_work}/export/${inject}")
      set(built TRUE)
    endif()
    run_repro("${case_work}/export/${inject}" 1 "\nfirst mismatch: ")
  endforeach()
endfunction()
inject_case(inject)

# --validate and REPRO_VALIDATE=1 ask for the layer: with no layer on the loader's path both fail
# naming it (exit 3); with it, the reproducer runs clean either way.
function(validate_case name)
  begin_case("${name}")
  save_calls(0)
  file(GLOB d LIST_DIRECTORIES true "${case_work}/saved/*-intersect.shadow.b0")
  export_call("${d}" "${case_work}/export")
  build_repro("${case_work}/export")
  file(MAKE_DIRECTORY "${case_work}/no-layers")
  foreach(how "--validate" "REPRO_VALIDATE=1")
    set(args "${case_work}/export")
    if(how STREQUAL "--validate")
      list(APPEND args --validate)
    else()
      set(ENV{REPRO_VALIDATE} 1)
    endif()
    set(ENV{VK_LAYER_PATH} "${case_work}/no-layers")
    execute_process(COMMAND "${case_work}/repro" ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE o ERROR_VARIABLE e)
    if(NOT rc EQUAL 3 OR NOT e MATCHES "VK_LAYER_KHRONOS_validation is not installed")
      fail("${how} without the layer: exit ${rc}, expected 3 naming the layer: ${o}${e}")
    endif()
    unset(ENV{VK_LAYER_PATH})
    execute_process(COMMAND "${case_work}/repro" ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE o ERROR_VARIABLE e)
    if(NOT rc EQUAL 0 OR NOT o MATCHES "\nequal: " OR "${o}${e}" MATCHES "validation:")
      fail("${how}: exit ${rc}, expected 0 and no validation message: ${o}${e}")
    endif()
    unset(ENV{REPRO_VALIDATE})
  endforeach()
endfunction()
validate_case(validate)

if(DEFINED CASE)
  if(NOT matched)
    message(FATAL_ERROR "cli_export.cmake: no case named '${CASE}'; cases: ${cli_export_cases}")
  endif()
  get_property(failures GLOBAL PROPERTY cli_export_failures)
  if(failures)
    message(FATAL_ERROR "${failures}")
  endif()
  message(STATUS "export ${CASE}: as expected")
endif()
