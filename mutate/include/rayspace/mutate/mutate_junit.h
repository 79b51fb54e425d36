// mutate's report as JUnit test cases (rayspace/junit.h), for --junit FILE (docs/library.md, "Results
// in CI").
#pragma once
#include <vector>

#include <nlohmann/json.hpp>

#include "rayspace/junit.h"

namespace rayspace::app {

// mutate's report: a suite per side (the mutants on Vulkan, on the simulated GPU) and one of the
// spirv-opt variants. A killed mutant passes; an unexplained survivor fails (the tests' gap); an
// equivalent, explained, stillborn or invalid one is skipped, saying which; a mutant that broke the
// tool is an error. A variant passes when it diffs equal.
std::vector<JUnitSuite> MutateJUnit(const nlohmann::json& report);

}  // namespace rayspace::app
