#pragma once
#include <cstddef>
#include <string>

#include "exit_codes.h"

namespace rayspace::app {

struct DiffArgs {
  std::string scene, size, data, report, inject, save_inputs, algo = "crsh", reduction = "hierarchical";
  int device = -1;
  int local_size = 64;
  int subdivision = 8, depth = 2;
  std::size_t split_bytes = 0;
  std::uint32_t max_groups = 0;
};

// Runs the whole frame with every pass on both backends (same inputs: the GPU's previous outputs)
// and compares every output bitwise. Returns kOk when all are equal, kDivergence when a pass diverges.
ExitCode RunDiff(const DiffArgs& args);

struct ReplayArgs {
  std::string dir, report, inject;
  int device = -1;
  int local_size = 64;
};

// Runs one saved pass call (diff --save-inputs) on both backends and compares. Returns kOk when equal,
// kDivergence when divergent, kNotReproduced when the comparison recorded at save time is not reproduced.
ExitCode RunReplay(const ReplayArgs& args);

}  // namespace rayspace::app
