# Each `rayspace bench` row is exactly the render command it names: the JSON's "render" options, given
# to `rayspace render` at the same size, give the row's digest and total tests (a row that quietly
# runs other options, as an --objects flat for render's auto, differs in its tests).
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DWORK=<scratch> -P cli_bench_rows.cmake
cmake_minimum_required(VERSION 3.19)  # string(JSON)
set(failures "")
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(scene "${SRC}/scenes/cornell-mirrors.json")
set(size 16x16)

execute_process(COMMAND "${RAYSPACE}" bench "${scene}" --sizes ${size} --repetitions 1 --json "${WORK}/bench.json"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "bench: exit ${rc}, expected 0:\n${out}${err}")
endif()
file(READ "${WORK}/bench.json" j)
string(JSON n LENGTH "${j}" results)
set(compared 0)
math(EXPR last "${n} - 1")
foreach(i RANGE ${last})
  string(JSON config GET "${j}" results ${i} config)
  string(JSON options GET "${j}" results ${i} render)
  string(JSON skipped ERROR_VARIABLE not_skipped GET "${j}" results ${i} skipped)
  if(not_skipped STREQUAL "")
    continue()  # a backend this machine cannot run: nothing to compare
  endif()
  string(JSON digest GET "${j}" results ${i} digests 0)
  string(JSON tests GET "${j}" results ${i} total_tests)
  separate_arguments(argv UNIX_COMMAND "${options}")
  execute_process(COMMAND "${RAYSPACE}" render "${scene}" --size ${size} ${argv} --no-oracle
                          --stats "${WORK}/${config}.json" --out "${WORK}/${config}.png"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE rout ERROR_VARIABLE rerr TIMEOUT 300)
  if(NOT rc EQUAL 0)
    set(failures "${failures}\n${config}: render ${options}: exit ${rc}:\n${rerr}")
    continue()
  endif()
  file(READ "${WORK}/${config}.json" s)
  string(JSON rdigest GET "${s}" digest)
  string(JSON rtests GET "${s}" total_tests)
  if(NOT rdigest STREQUAL digest OR NOT rtests STREQUAL tests)
    set(failures "${failures}\n${config}: bench digest ${digest}, ${tests} tests; render ${options}: digest ${rdigest}, ${rtests} tests")
  endif()
  math(EXPR compared "${compared} + 1")
endforeach()
# Every emulator row at least: a JSON without rows must not pass.
if(compared LESS 10)
  set(failures "${failures}\nonly ${compared} of ${n} rows compared")
endif()
if(failures)
  message(FATAL_ERROR "cli.bench.rows:${failures}")
endif()
message(STATUS "cli.bench.rows: ${compared} of ${n} rows are their render commands (digest and total tests)")
