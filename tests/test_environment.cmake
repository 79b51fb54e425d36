# The environment every test runs in (docs/verification.md, "Test tiers"). Included by
# tests/CMakeLists.txt for the tests it adds and at ctest time for the discovered doctest cases.
#
# Every test that touches Vulkan runs under the Khronos validation layer with synchronization
# validation (RAYSPACE_VALIDATE=1): any message fails the Vulkan call after which it was reported
# (gpu/include/rayspace/gpu/validation.h), so the test fails. The bootstrap installs the layer.
# lavapipe keeps nothing in a VkPipelineCache; its compiled shaders go to Mesa's disk cache, kept in
# the build tree so that every test and every run of the suite shares it whatever HOME is.
# OpenMP threads sleep while they wait rather than spin: two tests share two cores.
set(rayspace_test_environment_common "MESA_SHADER_CACHE_DIR=${PROJECT_BINARY_DIR}/mesa-shader-cache;OMP_WAIT_POLICY=PASSIVE")

# Tests that run without the layer, as anchored regular expressions over test names: planted faults
# and mutants change a kernel's instructions, not the host's calls, and each runs a configuration whose
# clean diff (cli.diff.<scene>.<algo>..., cli.backend) is validated. The layer costs such a test a
# quarter of its time. cli.diff.faults.first stays validated: it holds the path where one device runs a
# frame per fault.
set(rayspace_unvalidated
  "^cli\\.diff\\.fault\\."
  "^cli\\.diff\\.faults\\."
  "^cli\\.diff\\.relaxed\\."
  "^cli\\.diff\\.impact\\."
  "^cli\\.mutate\\."
  "^gpu\\.traverse\\.compact: every planted fault of the kernel is seen"
)
set(rayspace_validated_anyway "^cli\\.diff\\.faults\\.first$")

# Gives each of `tests` its environment.
function(rayspace_assign_environment)
  foreach(test IN LISTS ARGN)
    set(validate 1)
    foreach(pattern IN LISTS rayspace_unvalidated)
      if(test MATCHES "${pattern}")
        set(validate 0)
      endif()
    endforeach()
    if(test MATCHES "${rayspace_validated_anyway}")
      set(validate 1)
    endif()
    set_tests_properties("${test}" PROPERTIES ENVIRONMENT "RAYSPACE_VALIDATE=${validate};${rayspace_test_environment_common}")
  endforeach()
endfunction()
