# Helpers for the backend tests: render a frame on one backend and read its digest; render it on
# both and require the same digest and the same PNG bytes. Failures collect in `failures`.
# Needs RAYSPACE, DATA and WORK.

function(render_digest out_var name path size backend)
  # A data root that is not there is not given: a scene that needs none renders without it, one that
  # needs it says the root is not found (which the data-dependent tests skip on).
  set(data_args "")
  if(IS_DIRECTORY "${DATA}")
    set(data_args --data "${DATA}")
  endif()
  execute_process(COMMAND "${RAYSPACE}" render "${path}" ${data_args} --size ${size} --no-oracle
                          --backend ${backend} --out "${WORK}/${name}.png" --stats "${WORK}/${name}.json" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    set(failures "${failures}\n${name}: exit ${rc}: ${out}${err}" PARENT_SCOPE)
    set(${out_var} "" PARENT_SCOPE)
    return()
  endif()
  file(READ "${WORK}/${name}.json" j)
  string(JSON d GET "${j}" digest)
  string(JSON be GET "${j}" backend name)
  if(NOT be STREQUAL backend)
    set(failures "${failures}\n${name}: the statistics name backend '${be}'" PARENT_SCOPE)
  endif()
  set(${out_var} "${d}" PARENT_SCOPE)
endfunction()

function(same_frame name path size)
  render_digest(de ${name}_emu "${path}" ${size} emu ${ARGN})
  render_digest(dv ${name}_vulkan "${path}" ${size} vulkan ${ARGN})
  if(de STREQUAL "" OR NOT de STREQUAL dv)
    set(failures "${failures}\n${name}: digest emu '${de}' vs vulkan '${dv}'" PARENT_SCOPE)
    return()
  endif()
  file(SHA256 "${WORK}/${name}_emu.png" he)
  file(SHA256 "${WORK}/${name}_vulkan.png" hv)
  if(NOT he STREQUAL hv)
    set(failures "${failures}\n${name}: PNGs differ" PARENT_SCOPE)
  endif()
  set(failures "${failures}" PARENT_SCOPE)
endfunction()
