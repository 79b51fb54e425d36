// coverage: which of a kernel's source lines a run executed. The executor marks each instruction it
// runs for any lane (Dispatch::coverage, one byte per instruction of Program::code); a line counts as
// reached when any instruction OpLine gives it ran. An "equal" verdict says nothing of a line never
// reached. A module without OpLine is counted by instruction instead.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayspace/sim/program.h"

namespace rayspace::sim {

struct LineCoverage {
  bool by_line = true;              // false: the module has no OpLine, and the counts are instructions
  std::size_t reached = 0, total = 0;
  std::vector<std::string> missed;  // "reduce.comp:101-108": runs of unreached lines of one file, by file and line
};

LineCoverage CoverageOf(const Program& program, std::span<const std::uint8_t> executed);

}  // namespace rayspace::sim
