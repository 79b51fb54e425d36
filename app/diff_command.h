#pragma once
#include <cstddef>
#include <string>

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
// and compares every output bitwise. Returns 0 when all are equal, 4 when a pass diverges.
int RunDiff(const DiffArgs& args);

struct ReplayArgs {
  std::string dir, report, inject;
  int device = -1;
  int local_size = 64;
};

// Runs one saved pass call (diff --save-inputs) on both backends and compares. Returns 0 when equal,
// 4 when divergent, 5 when the comparison recorded at save time is not reproduced.
int RunReplay(const ReplayArgs& args);

}  // namespace rayspace::app
