// The commands' reports as JUnit test cases (rayspace/junit.h), for --junit FILE: what one test case
// is in each command is said here and in docs/library.md, "Results in CI".
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayspace/junit.h"

namespace rayspace::app {

// diff's report: a suite per frame (one, or one per planted fault with --inject-each); a case per
// pass call, failed when it diverged (message: its first mismatch), and a case "frame" that fails
// when a checker or an error stopped the frame without a divergent call.
std::vector<JUnitSuite> DiffJUnit(const nlohmann::json& report);

// A diff report call's first differing buffer (its "calls" entry), as "BUFFER[INDEX]: expected E,
// actual A (M of N elements differ)", or its element counts when they differ; "" when none differs.
std::string FirstMismatch(const nlohmann::json& call);

// mutate's report: a suite per side (the mutants on Vulkan, on the simulated GPU) and one of the
// spirv-opt variants. A killed mutant passes; an unexplained survivor fails (the tests' gap); an
// equivalent, explained, stillborn or invalid one is skipped, saying which; a mutant that broke the
// tool is an error. A variant passes when it diffs equal.
std::vector<JUnitSuite> MutateJUnit(const nlohmann::json& report);

}  // namespace rayspace::app
