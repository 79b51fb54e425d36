# `rayspace reproduce thesis`: the report and its tables are byte-identical whether written by one run,
# a second run, a run with --jobs 2, a run interrupted (--stop-after, as Ctrl-C) and resumed, or three
# shards merged; an interrupted run leaves no partial file; bad arguments exit 2 with one line.
# Frames are 16x16 (the hidden --size), and 27 of the 75 configurations (--only), to keep it quick.
# The first run also writes --junit, validated against docs/schemas/junit.xsd.
# Run: cmake -DRAYSPACE=<exe> -DSRC=<source dir> -DDATA=<data root> -DXMLLINT=<xmllint> -DWORK=<scratch> -P cli_reproduce.cmake
cmake_minimum_required(VERSION 3.19)
include(${CMAKE_CURRENT_LIST_DIR}/cli_expect.cmake)
cli_require_data(cli.reproduce bunny/bun_zipper_res4.ply bunny/bun_zipper_res3.ply bunny/bun_zipper.ply dragon/dragon.obj
                 suzanne/suzanne.obj)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
unset(ENV{RAYSPACE_DATA})  # each run names its data root, or none on purpose
set(FAILURES "")
set(CASES 0)
set(common thesis --size 16x16 --only "s8 d[23]|quadtree" --scenes "${SRC}/scenes" --data "${DATA}")

# Runs reproduce with ARGN in WORK; expects exit 0.
function(run name)
  execute_process(COMMAND "${RAYSPACE}" reproduce ${ARGN} WORKING_DIRECTORY "${WORK}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
  if(NOT rc EQUAL 0)
    set(FAILURES "${FAILURES}\n  [${name}] exit ${rc}, expected 0:\n${out}${err}" PARENT_SCOPE)
  endif()
  set(last_err "${err}" PARENT_SCOPE)
endfunction()

# same_files(NAME A B FILE...): each FILE byte-identical in directories A and B (under WORK).
function(same_files name a b)
  foreach(f ${ARGN})
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${WORK}/${a}/${f}" "${WORK}/${b}/${f}" RESULT_VARIABLE differ)
    if(differ)
      set(FAILURES "${FAILURES}\n  [${name}] ${b}/${f} differs from ${a}/${f}")
    endif()
  endforeach()
  set(FAILURES "${FAILURES}" PARENT_SCOPE)
endfunction()

# The byte-identical set of directory DIR: report.md, results.json, every table and every plot.
function(same name dir)
  file(GLOB tables RELATIVE "${WORK}/first" "${WORK}/first/tables/*.csv")
  file(GLOB plots RELATIVE "${WORK}/first" "${WORK}/first/plots/*.svg")
  list(LENGTH tables n)
  list(LENGTH plots np)
  if(n LESS 27 OR np LESS 1)
    set(FAILURES "${FAILURES}\n  [${name}] ${n} tables and ${np} plots, expected at least 27 and 1" PARENT_SCOPE)
  endif()
  foreach(f report.md results.json ${tables} ${plots})
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${WORK}/first/${f}" "${WORK}/${dir}/${f}" RESULT_VARIABLE differ)
    if(differ)
      set(FAILURES "${FAILURES}\n  [${name}] ${dir}/${f} differs from first/${f}" PARENT_SCOPE)
    endif()
  endforeach()
endfunction()

run(first ${common} --out first --junit first-junit.xml)
# The relation checks as JUnit, valid under the schema, a case per relation and place.
execute_process(COMMAND "${XMLLINT}" --noout --schema "${SRC}/docs/schemas/junit.xsd" "${WORK}/first-junit.xml"
                RESULT_VARIABLE valid ERROR_VARIABLE why)
if(NOT valid EQUAL 0)
  set(FAILURES "${FAILURES}\n  [first] first-junit.xml not valid under junit.xsd: ${why}")
else()
  file(READ "${WORK}/first-junit.xml" junit)
  if(NOT junit MATCHES "<testsuites name=\"rayspace reproduce\" tests=\"[1-9][0-9]*\"" OR NOT junit MATCHES "classname=\"reproduce[.]CRSH total &lt; RAH total\"")
    set(FAILURES "${FAILURES}\n  [first] first-junit.xml lacks the relation checks:\n${junit}")
  endif()
endif()
foreach(f report.md results.json run.json timings.md timings.csv tables/table-4.01.csv tables/table-4.24.csv
          tables/table-quadtree.csv tables/table-summary.csv plots/table-4.04.svg)
  if(NOT EXISTS "${WORK}/first/${f}")
    set(FAILURES "${FAILURES}\n  [first] no ${f}")
  endif()
endforeach()
# expect_in(TAG FILE NEEDLE...): each needle is in FILE (under WORK), else a failure tagged TAG.
function(expect_in tag file)
  file(READ "${WORK}/${file}" text)
  foreach(needle ${ARGN})
    string(FIND "${text}" "${needle}" at)
    if(at EQUAL -1)
      set(FAILURES "${FAILURES}\n  [${tag}] ${file} lacks '${needle}'")
    endif()
  endforeach()
  set(FAILURES "${FAILURES}" PARENT_SCOPE)
endfunction()

expect_in(first first/report.md "## Summary" "| CRSH total < RAH total |" "## Table 4.1: OFFICE, subdivision 8, depth 2"
          "## Table 4.24: totals, subdivision 16, depth 4" "published fails (632,408,864 != 610,873,884)")
file(READ "${WORK}/first/report.md" report)
if(report MATCHES "${WORK}|${SRC}|${DATA}")
  set(FAILURES "${FAILURES}\n  [first] report.md names a machine path")
endif()

run(rerun ${common} --out first)
same(rerun first)
run(jobs ${common} --out jobs --jobs 2)
same(jobs jobs)

# Interrupted after 3 configurations with 2 jobs in flight: a non-zero exit, 3 results, no partial file.
execute_process(COMMAND "${RAYSPACE}" reproduce ${common} --out stopped --jobs 2 --stop-after 3 WORKING_DIRECTORY "${WORK}"
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET TIMEOUT 300)
file(GLOB done "${WORK}/stopped/results/*.json")
file(GLOB partial "${WORK}/stopped/results/.*" "${WORK}/stopped/.*")
list(LENGTH done n)
if("${rc}" STREQUAL "0" OR NOT n EQUAL 3 OR partial OR EXISTS "${WORK}/stopped/report.md")
  set(FAILURES "${FAILURES}\n  [stop-after] exit '${rc}', ${n} results (expected non-zero, 3), partial files: '${partial}'")
endif()
run(resume ${common} --out stopped --resume)
same(resume stopped)

foreach(i 0 1 2)
  run(shard-${i} ${common} --out shard${i} --shard ${i}/3)
endforeach()
run(merge merge merged shard0 shard1 shard2)
same(merge merged)


# target_sharded(TARGET MIN_FILES NEEDLE...): TARGET at 16x16, one run against two shards merged: the
# report, results, every table and plot byte-identical (at least MIN_FILES of them), each NEEDLE in
# the first run's report.
function(target_sharded target min_files)
  set(args ${target} --size 16x16 --scenes "${SRC}/scenes" --data "${DATA}")
  run(${target}-first ${args} --out ${target}-first)
  foreach(i 0 1)
    run(${target}-shard-${i} ${args} --out ${target}-shard${i} --shard ${i}/2)
  endforeach()
  run(${target}-merge merge ${target}-merged ${target}-shard0 ${target}-shard1)
  file(GLOB files RELATIVE "${WORK}/${target}-first" "${WORK}/${target}-first/tables/*.csv" "${WORK}/${target}-first/plots/*.svg")
  list(LENGTH files n)
  if(n LESS min_files)
    set(FAILURES "${FAILURES}\n  [${target}] ${n} tables and plots, expected at least ${min_files}")
  endif()
  same_files(${target}-merge ${target}-first ${target}-merged report.md results.json ${files})
  expect_in(${target} ${target}-first/report.md ${ARGN})
  set(FAILURES "${FAILURES}" PARENT_SCOPE)
endfunction()

# roger: figure 13(c) adds 8x8 and 32x32.
target_sharded(roger 10 "# Roger et al. 2007: its claims and ours" "## Roger et al. 2007, figure 9(b)"
               "## Roger et al. 2007, figure 13(c)" "plots/table-roger-9b.svg")
file(READ "${WORK}/roger-first/timings.md" timings)
string(FIND "${timings}" "figure 9(a): share of frame time per phase" at)
if(at EQUAL -1)
  set(FAILURES "${FAILURES}\n  [roger] timings.md lacks the figure 9(a) phase shares")
endif()
# Figure 14: the bunny's frames beside Embree's, and both relations judged per hierarchy shape.
expect_in(roger roger-first/timings.md "figure 14(b, c): the frame against a BVH's" "| BUNNY res4 rah-quadtree 16x16 | 948 |"
          "- faster than a BVH on a reflecting bunny (fig. 14(c): about 2x), rah-quadtree on BUNNY res3:"
          "- against a BVH, slower on simple scenes, faster on complex ones (fig. 14(b)), rah s8 d2:")
target_sharded(toczek 4 "# Toczek et al. 2010: its tables and ours" "## Toczek et al. table 1" "## Toczek et al. table 2"
               "| the node order changes nodes per ray by at most 20% (table 1) |" "| DRAGON | ours | 100,002 |"
               "| back-face culling lowers nodes per ray (table 1) | bunny, earliest-first, heads and frustum culling disabled |")
# hunt-mark: table 5 (counts) in report.md, table 1 (times) and its plot in timings.md.
target_sharded(hunt-mark 2 "# Hunt and Mark 2008: its tables and ours" "## Hunt and Mark table 5"
               "| a 3D perspective grid needs fewer cells per soft-shadow ray than a regular grid (table 5) | SPONZA-SOFT |"
               "| Courtyard | published | 54x54x54 (157,464 cells) | 52.0 | 200x200x4 | 12.7 |"
               "## Hunt and Mark's grid sizes, fitted" "| SPONZA-SOFT | 90x41x43 (158,670 cells) |"
               "| CONFERENCE-SOFT | 100x25x64 (160,000 cells) |")
expect_in(hunt-mark hunt-mark-first/timings.md "## Hunt and Mark table 1" "| BUNNY-69K | ours | 70,291 |" "timing-plots/table-hunt-1.svg"
          "rays per second fall from the smallest bunny to the largest (table 1) (eye rays)"
          "rays per second fall from the smallest bunny to the largest (table 1) (hard shadows)"
          "(the eye's grid)" "(the light's grid)")
if(NOT EXISTS "${WORK}/hunt-mark-first/timing-plots/table-hunt-1.svg")
  set(FAILURES "${FAILURES}\n  [hunt-mark] no timing-plots/table-hunt-1.svg")
endif()
# The toczek target's results stay out of the thesis's phase timings.
file(READ "${WORK}/toczek-first/timings.csv" toczek_timings)
# Its own times (section 4's 6 lists against 1) are there; none of its frames is in the thesis's phase table.
if(toczek_timings MATCHES "tl K[0-9]" OR NOT toczek_timings MATCHES "6 lists trace faster than 1")
  set(FAILURES "${FAILURES}\n  [toczek] timings.csv holds toczek frames in the phase table, or lacks the 6-lists claim")
endif()
file(MAKE_DIRECTORY "${WORK}/nobunny")
expect_error(NAME roger-data NEEDLES "bunny/bun_zipper_res4.ply: missing under the data root"
             ARGS reproduce roger --scenes "${SRC}/scenes" --data "${WORK}/nobunny" --out z)

expect_error(NAME shard-range NEEDLES "--shard '3/3': needs 0 <= I < N" ARGS reproduce ${common} --shard 3/3)
expect_error(NAME shard-form NEEDLES "--shard 'x': expected I/N" ARGS reproduce ${common} --shard x)
expect_error(NAME jobs NEEDLES "--jobs" ARGS reproduce ${common} --jobs 0)
expect_error(NAME quick-full NEEDLES "--quick and --full exclude each other" ARGS reproduce ${common} --quick --full)
expect_error(NAME target NEEDLES "unknown target 'nope'" ARGS reproduce nope)
expect_error(NAME only NEEDLES "--only 'zzz': matches no configuration" ARGS reproduce thesis --scenes "${SRC}/scenes" --only zzz)
expect_error(NAME other-run NEEDLES "--out first: holds results of another run" ARGS reproduce thesis --size 16x16 --scenes "${SRC}/scenes" --data "${DATA}" --out first --only OFFICE)
expect_error(NAME merge-missing NEEDLES "shard 1/3 is missing" ARGS reproduce merge m2 shard0 shard2)
expect_error(NAME merge-twice NEEDLES "shard 0/3 given twice: shard0 and shard0" ARGS reproduce merge m3 shard0 shard0 shard1 shard2)
expect_error(NAME merge-nodir NEEDLES "nodir: no such directory" ARGS reproduce merge m4 shard0 nodir)
expect_error(NAME merge-notshard NEEDLES "first: shard 0/1, but shard0 is one of 3" ARGS reproduce merge m5 shard0 first)
file(MAKE_DIRECTORY "${WORK}/nodata")
expect_error(NAME data NEEDLES "sponza_dabrovic/sponza.mtl: missing under the data root" "rayspace data check"
             ARGS reproduce thesis --scenes "${SRC}/scenes" --data "${WORK}/nodata" --out y)
if(EXISTS "${WORK}/y")
  set(FAILURES "${FAILURES}\n  [data] a run refused for its data left y/ behind")
endif()
# Without --data the data root is RAYSPACE_DATA, as for render; with neither, the error says so. The
# run is of one configuration, so its plots have a single point (a range of its own, no warning).
set(ENV{RAYSPACE_DATA} "${DATA}")
run(env-data roger --size 16x16 --only "BUNNY res4 rah-quadtree 16x16$" --scenes "${SRC}/scenes" --out env-data)
if(NOT EXISTS "${WORK}/env-data/report.md")
  set(FAILURES "${FAILURES}\n  [env-data] no report.md from a run with RAYSPACE_DATA")
endif()
unset(ENV{RAYSPACE_DATA})
expect_error(NAME no-data-root NEEDLES "bun_zipper_res4.ply: missing under the data root" "no data root: give --data DIR or set RAYSPACE_DATA"
             ARGS reproduce roger --size 16x16 --only "BUNNY res4 rah-quadtree 16x16$" --scenes "${SRC}/scenes" --out z2)
# The ablation: SPONZA's 12 configurations under the defaults and each faithful switch, a row each.
run(ablation thesis-ablation --size 16x16 --scenes "${SRC}/scenes" --data "${DATA}" --out ablation)
expect_in(ablation ablation/report.md "# CRSH thesis: the faithful switches on SPONZA" "| (rayspace's defaults) |"
          "| --cone-test printed |" "| --hash-order polar-first --hash-bits 8 |" "| --one-object |" "| --child-merge pairwise |"
          "| --shadow-rule lit |")
# The fit, on a search of a few frames (protocol 2, the default): its summary, its frames and the
# fitted scene, which renders.
run(fit thesis --fit --fit-small --scenes "${SRC}/scenes" --data "${DATA}" --out fit)
foreach(f fit-thesis-sponza-2.json fit-thesis-sponza-2-frames.json sponza-thesis-fit-2.json)
  if(NOT EXISTS "${WORK}/fit/${f}")
    set(FAILURES "${FAILURES}\n  [fit] no ${f}")
  endif()
endforeach()
expect_in(fit fit/fit-thesis-sponza-2.json "\"best\"" "\"sensitivity\"" "\"starts\"" "\"level2_hits\": 32686844" "\"protocol\": 2"
          "\"min_lit_share\": 0.5" "\"lit_share\"")
expect_in(fit fit/sponza-thesis-fit-2.json "\"name\": \"sponza-thesis-fit-2\"")
execute_process(COMMAND "${RAYSPACE}" render "${WORK}/fit/sponza-thesis-fit-2.json" --data "${DATA}" --size 16x16 --no-oracle --out fit.png
                WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
if(NOT rc EQUAL 0)
  set(FAILURES "${FAILURES}\n  [fit] the fitted scene does not render: ${err}")
endif()
expect_error(NAME fit-target NEEDLES "--fit toczek: only the thesis's fit" ARGS reproduce toczek --fit --out f2)
expect_error(NAME fit-shard NEEDLES "--fit takes none of --shard" ARGS reproduce --fit --shard 1/2 --out f3)
expect_error(NAME fit-small NEEDLES "--fit-small: only with --fit" ARGS reproduce thesis --fit-small --out f4)
expect_error(NAME fit-protocol NEEDLES "--fit-protocol: only with --fit" ARGS reproduce thesis --fit-protocol 1 --out f5)
expect_error(NAME fit-protocol-range NEEDLES "--fit-protocol" ARGS reproduce thesis --fit --fit-protocol 3 --out f6)
expect_error(NAME scenes NEEDLES "nowhere/office.json: cannot open scene file" ARGS reproduce thesis --scenes nowhere --out x)

if(NOT FAILURES STREQUAL "")
  message(FATAL_ERROR "cli.reproduce: failures:${FAILURES}")
endif()
message(STATUS "cli.reproduce: every run byte-identical, ${CASES} bad arguments refused")
