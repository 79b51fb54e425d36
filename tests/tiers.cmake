# Test tiers (docs/verification.md, "Test tiers"). Every test carries exactly one tier label:
#   default  scripts/test.sh: what a developer runs before each commit (docs/verification.md gives its time)
#   full     scripts/test.sh --full and CI add these: slow by nature, each one's claim guarded in the
#            default tier by a cheaper test (the comment beside each pattern names it)
# and a TIMEOUT. Included twice: by tests/CMakeLists.txt for the tests it adds, and at ctest time for
# the doctest cases discovered after the build (tiers_discovered.cmake in the build's tests/), so one
# list decides both.

# Full-tier tests, as anchored regular expressions over test names.
set(rayspace_full_tier
  # The mutation sample (20 commit-seeded kernel mutants through every configuration) and the mutants
  # only the lists' kernel cases and the added scenes kill: the machinery is cli.mutate.targeted's
  # (named mutants killed by the diff, a kernel case and the clamping device).
  "^cli\\.mutate\\.(sample|configs)$"
  # Mutants lavapipe runs benignly killed on the simulated GPU: the default tier's cli.simulate.backend
  # catches the planted faults lavapipe runs benignly by the same checkers, and cli.mutate.targeted runs
  # the mutate machinery.
  "^cli\\.mutate\\.backends$"
  # Random configurations on the data scenes: the same cases on the bundled scenes stay.
  "^fused path: the same pairs, statistics and digest as the passes, on random configurations on Sponza$"
  "^grid lanes: the pass's walks, statistics and digest on the data scenes and random configurations$"
  # Sponza's diffs: each configuration is diffed on office and cornell-mirrors in the default tier.
  "^cli\\.diff\\.sponza\\."
  # The product of local sizes and schedules: each local size and each schedule once stays
  # (<scene>.schedule.32.forward, .64.reverse, .256.random:7 on office and cornell-mirrors).
  "^cli\\.diff\\.(office|cornell-mirrors)\\.schedule\\.(32\\.(reverse|random:7)|64\\.(forward|random:7)|256\\.(forward|reverse))$"
  # The device-like faults under the bitwise comparison: each is a difference, which the planted
  # faults show bitwise diffs catch; relaxed.bitwise.intersect:approx-div stays, and every
  # relaxed case (the relaxed model accepting each fault: relaxed.glass, relaxed.office, ...) stays.
  "^cli\\.diff\\.relaxed\\.bitwise\\.(build|hash|raster|raygen|shade|surfaces|traverse)"
  # The workgroup faults in the emulated mirrors, pass by kind: the checker names a kind whatever pass
  # plants it; every kind stays on trim (fault.trim:<kind>@emu, with the case "trim: each planted
  # workgroup fault is named by the checker"), and each pass's dropped barrier stays.
  "^cli\\.diff\\.fault\\.(compress|sort|decompress|reduce):(divergent-barrier|subgroup-32|shared-off-by-one)@emu$"
  # Local sizes 32 and 256 at the forward schedule: cornell-mirrors.schedule.32.forward and
  # .256.random:7 diff the same scene at those sizes.
  "^cli\\.diff\\.cornell\\.crsh\\.local-size-(32|256)$"
  # reproduce end to end (byte-identical reports across reruns, --jobs, --resume and shards; thesis
  # --quick): the doctest cases "reproduce: the report does not depend on --jobs ..." and "reproduce:
  # merge takes every shard of one run exactly once" hold --jobs and shards on small runs.
  "^cli\\.reproduce"
  # Every exported call of two 32x32 diffs on the simulator: cli.simulate.sample runs one call of every
  # pass, a planted fault and the refusal.
  "^cli\\.simulate\\.all$"
  # lavapipe at every width on three scenes at 64x64 and five local sizes: cli.widths.sample diffs
  # widths 4 and 16 at local sizes 7, 12, 32 and 256 on cornell-mirrors.
  "^cli\\.widths\\.all$"
  # The simulated backend on 32x32 frames under every tracer: cli.simulate.backend diffs five
  # configurations at 16x16.
  "^cli\\.simulate\\.backend-all$"
  # The options that reach a user kernel's unreached lines, probed over 26 configurations (minutes):
  # cli.simulate.sample shows --reduction scan reaching the lines a default frame misses.
  "^cli\\.simulate\\.coverage-options$"
  # The worst-conformant device and the subgroup layouts on whole frames: gpu.sim's "device math: ..."
  # cases, "the worst-conformant device fuses ...", "subgroup layouts ..." and "a boolean
  # specialization constant ..." hold the same claims on small kernels.
  "^cli\\.simulate\\.device-model$"
  # Every pass launched or refused with an example that launches it: cli.kernel refuses a pass a run
  # never launched, naming its example, and the registry case maps every pass to its kernel.
  "^cli\\.kernel\\.reach$"
  # The Debian packages built (cpack) and used by a consumer project: install.consumer does the same
  # from `cmake --install`, with the same consumer and the trees hidden.
  "^install\\.deb$"
  # office on both backends, image for image: cli.diff.office.crsh and .rah diff its passes bitwise.
  "^cli\\.backend\\.office$"
  # Five schedules by four subgroup sizes at 64x64: cli.simulate.backend runs a random schedule at
  # subgroup size 4, and gpu.sim executor cases check the orders themselves.
  "^cli\\.simulate\\.schedules\\."
  # A frame beyond one storage binding (2048x1152): the same parts and paging on small frames with
  # --split-bytes in cli.backend and cli.diff (studs.crsh.paged, cornell.crsh.paged, ...).
  "^cli\\.large_frame$"
  # Every call of each method and ray kind exported, and the same with small bindings: clean.methods
  # exports one call of each method, fault.paged.* exports paged calls.
  "^cli\\.export\\.clean\\.(passes|paged)$"
  # The data root's scenes (Sponza, the bunny, the conference room): the same claims on the bundled
  # scenes in cli.backend, cli.tl, cli.grid, cli.hierarchy and the doctest cases.
  "^cli\\.(data|tl\\.data|grid\\.data|backend\\.sponza|hierarchy\\.sponza|sponza_thesis)$"
  "^docs\\.numbers$"
  # Hundreds of malformed scenes, meshes, flag values and output paths: each class of bad input has
  # its cases in cli.errors, cli.inputs and cli.outputs.
  "^hostile\\.inputs$"
)

# Seconds a test may take before ctest stops it, unless it sets its own TIMEOUT: the slowest test
# without one takes under a minute on the project's 2-core machine, even beside another.
set(rayspace_default_timeout 300)

# Labels `tests` with their tier and gives each one without a TIMEOUT the default one.
function(rayspace_assign_tiers)
  foreach(test IN LISTS ARGN)
    set(tier default)
    foreach(pattern IN LISTS rayspace_full_tier)
      if(test MATCHES "${pattern}")
        set(tier full)
      endif()
    endforeach()
    set_tests_properties("${test}" PROPERTIES LABELS ${tier})
    if(COMMAND get_test_property)
      get_test_property("${test}" TIMEOUT timeout)
    else()
      set(timeout NOTFOUND)
    endif()
    if(NOT timeout)
      set_tests_properties("${test}" PROPERTIES TIMEOUT ${rayspace_default_timeout})
    endif()
  endforeach()
endfunction()
