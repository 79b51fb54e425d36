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
# A rerun's verdict replaces the full run's: a.comp's survivor killed later makes a.comp 100 % and all
# 3 / 3; a rerun naming a mutant the report lacks is refused.
execute_process(COMMAND "${PYTHON}" "${SRC}/scripts/mutation_table.py" "${SRC}/tests/scripts/mutate_report_sample.json"
                        --rerun "${SRC}/tests/scripts/mutate_rerun_sample.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE rerun ERROR_VARIABLE err)
foreach(line "| `a.comp` | p1, p2, p3, ... | 3 | 2 | 0 | 1 + 0 | 100 % |" "| **all** | | **6** | **3** | **0** | **1 + 1** | **100.0 %** |")
  string(FIND "${rerun}" "${line}" at)
  if(at EQUAL -1 OR NOT rc EQUAL 0)
    string(APPEND FAILURES "\nwith --rerun, missing: ${line} (exit ${rc})")
  endif()
endforeach()
execute_process(COMMAND "${PYTHON}" "${SRC}/scripts/mutation_table.py" "${SRC}/tests/scripts/mutate_rerun_sample.json"
                        --rerun "${SRC}/tests/scripts/mutate_report_sample.json"
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "is not in")
  string(APPEND FAILURES "\na rerun of unknown ids: exit ${rc}, ${err}")
endif()
if(FAILURES)
  message(FATAL_ERROR "scripts.mutation_table:${FAILURES}\n${out}")
endif()
