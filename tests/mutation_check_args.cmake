# scripts/mutation_check.py's argument contract and its sample, run as
#   cmake -DSCRIPT=<scripts/mutation_check.py> -DSRC=<source dir> -DWORK=<scratch dir> -P mutation_check_args.cmake
# The sample is a function of the seed, the count and the sources: the same call lists the same
# mutants, another seed others. A bad call is exit code 2 with one line on stderr naming the argument.
# Only --dry-run runs here; a real run rebuilds the unit tests once per mutant (docs/mutation.md).
cmake_minimum_required(VERSION 3.19)
foreach(var SCRIPT SRC WORK)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "mutation_check_args.cmake: pass -D${var}=...")
  endif()
endforeach()
set(FAILURES "")

function(dry_run out_var)
  execute_process(COMMAND python3 "${SCRIPT}" --source "${SRC}" --dry-run ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
  if(NOT rc EQUAL 0)
    set(FAILURES "${FAILURES}\n  --dry-run ${ARGN}: exit ${rc}: ${err}" PARENT_SCOPE)
  endif()
  set(${out_var} "${out}" PARENT_SCOPE)
endfunction()

dry_run(a --seed 3 --count 3 --files emu/src/resolve.cpp emu/src/shade.cpp)
dry_run(b --seed 3 --count 3 --files emu/src/resolve.cpp emu/src/shade.cpp)
dry_run(c --seed 4 --count 3 --files emu/src/resolve.cpp emu/src/shade.cpp)
if(NOT a STREQUAL b)
  set(FAILURES "${FAILURES}\n  the same seed listed different mutants:\n${a}\n${b}")
endif()
if(a STREQUAL c)
  set(FAILURES "${FAILURES}\n  seeds 3 and 4 listed the same mutants:\n${a}")
endif()
string(REGEX MATCHALL "\n  .(resolve|shade). emu/src/(resolve|shade)\\.cpp:[0-9]+: " listed "${a}")
list(LENGTH listed n)
if(NOT n EQUAL 3 OR NOT a MATCHES "^seed 3: 3 of [0-9]+ mutants over 2 files")
  set(FAILURES "${FAILURES}\n  expected 3 mutants of resolve.cpp and shade.cpp with their pass and file:line:\n${a}")
endif()

# --tiers: the sample reaches beyond the emulator (app/ is the first group in order) and adds the
# kernels' mutants apart.
dry_run(t --tiers --seed 2 --count 4 --kernels 2)
string(REGEX MATCHALL "\n  \\[kernel [a-z_]+\\] gpu/shaders/[a-z_]+\\.comp:[0-9]+: " kernels "${t}")
list(LENGTH kernels nk)
if(NOT t MATCHES "^seed 2: 4 of [0-9]+ mutants over [0-9]+ files\nseed 2: 2 of [0-9]+ kernel mutants" OR NOT nk EQUAL 2
   OR NOT t MATCHES "\n  \\[app\\] app/[a-z_]+\\.cpp:[0-9]+: ")
  set(FAILURES "${FAILURES}\n  expected 4 source mutants (app/ among them) and 2 kernel mutants:\n${t}")
endif()

# bad_call(<needle> <arg>...): exit 2, one line on stderr containing the needle.
function(bad_call needle)
  execute_process(COMMAND python3 "${SCRIPT}" --source "${SRC}" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
  string(REGEX MATCHALL "\n" newlines "${err}")
  list(LENGTH newlines lines)
  string(FIND "${err}" "${needle}" at)
  if(NOT "${rc}" STREQUAL "2" OR NOT lines EQUAL 1 OR at EQUAL -1)
    set(FAILURES "${FAILURES}\n  [${ARGN}] exit '${rc}' (expected 2), ${lines} stderr lines (expected 1), needle '${needle}': ${err}" PARENT_SCOPE)
  endif()
endfunction()
bad_call("--count 0" --dry-run --count 0)
bad_call("--files 'emu/src/no_such.cpp'" --dry-run --files emu/src/no_such.cpp)
bad_call("--tests '('" --dry-run --tests "(")
bad_call("--seed" --dry-run --seed many)
bad_call("--no-such-flag" --no-such-flag)
bad_call("--build" --dry-run --build "${SRC}/no-such-build")
bad_call("--tiers builds its own copy" --dry-run --tiers --build "${SRC}")
bad_call("--kernels -1" --dry-run --tiers --kernels -1)

# --resume: only with --tiers and a --report, with that copy's report; without a copy under --work
# (another checkout) the copy is made from the report's source commit, which must be a clean one.
bad_call("--resume goes on with a --tiers run's --report" --resume --tiers)
bad_call("--resume goes on with a --tiers run's --report" --resume --report r.json)
set(work "${WORK}/mutation_check_args")
file(REMOVE_RECURSE "${work}")
bad_call("cannot read --report '${work}/r.json'" --tiers --resume --report "${work}/r.json" --work "${work}")
file(WRITE "${work}/r.json" "{\"seed\": 1, \"count\": 40, \"source_commit\": \"abc+dirty\", \"mutants\": []}")
bad_call("the report's source 'abc+dirty' is not a clean commit" --tiers --resume --report "${work}/r.json" --work "${work}")
file(WRITE "${work}/r.json" "{\"seed\": 1, \"count\": 40, \"source_commit\": \"0123456789012345678901234567890123456789\", \"mutants\": []}")
bad_call("commit 0123456789012345678901234567890123456789 is not in" --tiers --resume --report "${work}/r.json" --work "${work}")
# A commit that is there: the copy is made from it (then the report's seed, not this run's, stops it).
# Only where SRC is a checkout's top: a copy of the tree inside another checkout (mutation_check.py's
# own copy under build/) would find that checkout's commits.
execute_process(COMMAND git -C "${SRC}" rev-parse HEAD RESULT_VARIABLE git_rc OUTPUT_VARIABLE head OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
execute_process(COMMAND git -C "${SRC}" rev-parse --show-toplevel OUTPUT_VARIABLE top OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
file(REAL_PATH "${SRC}" src_real)
if(git_rc EQUAL 0 AND top STREQUAL src_real)
  file(REMOVE_RECURSE "${work}/src")
  file(WRITE "${work}/r.json" "{\"seed\": 9, \"count\": 40, \"source_commit\": \"${head}\", \"mutants\": []}")
  bad_call("is of another run (source ${head}, seed 9" --tiers --resume --report "${work}/r.json" --work "${work}")
  file(READ "${work}/src/.source_commit" marker)
  if(NOT marker STREQUAL "${head}\n" OR NOT EXISTS "${work}/src/scripts/mutation_check.py")
    set(FAILURES "${FAILURES}\n  --resume without a copy: no copy of ${head} under ${work}/src (marker '${marker}')")
  endif()
endif()
file(REMOVE_RECURSE "${work}")
file(WRITE "${work}/src/.source_commit" "abc\n")
bad_call("cannot read --report '${work}/r.json'" --tiers --resume --report "${work}/r.json" --work "${work}")
file(WRITE "${work}/r.json" "{\"seed\": 1, \"count\": 40, \"source_commit\": \"def\", \"mutants\": []}")
bad_call("is of another run (source def" --tiers --resume --report "${work}/r.json" --work "${work}")
file(REMOVE_RECURSE "${work}")

# The tests a mutant's tier run names as its killers: ctest's FAILED list, doctest names with spaces
# and parentheses included (an empty list made the report's killed_by empty).
execute_process(COMMAND python3 -c "import importlib.util, sys
spec = importlib.util.spec_from_file_location('m', sys.argv[1]); m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m)
out = 'x\\nThe following tests FAILED:\\n\\t704 - cli.kernel.reach (Failed)\\n\\t183 - cone simd: lanes (all of them) equal (Timeout)\\nErrors while running CTest\\n'
print('|'.join(m.failed_tests(out)))" "${SCRIPT}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out STREQUAL "cli.kernel.reach (Failed)|cone simd: lanes (all of them) equal (Timeout)\n")
  set(FAILURES "${FAILURES}\n  failed_tests: exit ${rc}: '${out}' ${err}")
endif()

if(FAILURES)
  message(FATAL_ERROR "mutation_check.py:${FAILURES}")
endif()
