// diff's report as JUnit test cases (rayspace/junit.h), for --junit FILE: what one test case is is
// said here and in docs/library.md, "Results in CI".
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

}  // namespace rayspace::app
