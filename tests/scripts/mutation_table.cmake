# scripts/mutation_table.py on a six-mutant report whose table was counted by hand: a.comp 1 killed,
# 1 survived (out-of-bounds), 1 proved equivalent (50 %); b.glsl 1 killed, 1 argued equivalent, 1
# stillborn (100 %); all 2 / 3 = 66.7 %. And a missing report: one line, non-zero exit.
execute_process(COMMAND "${PYTHON}" "${SRC}/scripts/mutation_table.py" "${SRC}/tests/scripts/mutate_report_sample.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(FAILURES "")
foreach(line "| `a.comp` | p1, p2, p3, ... | 3 | 1 | 1 | 1 + 0 | 50 % |"
             "| `b.glsl` | p1 | 3 | 1 | 0 | 0 + 1 | 100 % |"
             "| **all** | | **6** | **2** | **1** | **1 + 1** | **66.7 %** |"
             "Also: 1 stillborn (not scored)."
             "**out-of-bounds** (1)"
             "- `a.comp:2:9:constant:2u` — `s[1u]`: a read past the array"
             "**equivalent** (1)")
  string(FIND "${out}" "${line}" at)
  if(at EQUAL -1)
    string(APPEND FAILURES "\nmissing: ${line}")
  endif()
endforeach()
if(NOT rc EQUAL 0)
  string(APPEND FAILURES "\nexit ${rc}: ${err}")
endif()
execute_process(COMMAND "${PYTHON}" "${SRC}/scripts/mutation_table.py" "${SRC}/tests/scripts/no-such-report.json"
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "no-such-report.json")
  string(APPEND FAILURES "\na missing report: exit ${rc}, ${err}")
endif()
if(FAILURES)
  message(FATAL_ERROR "scripts.mutation_table:${FAILURES}\n${out}")
endif()
