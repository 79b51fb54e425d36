#pragma once
#include <string>

namespace rayspace::app {

struct DiffArgs {
  std::string scene, size, data, report, inject;
  int device = -1;
  int local_size = 64;
};

// Runs every pass that has a Vulkan kernel on both backends with the same input and compares the
// outputs bitwise. Returns 0 when all are equal, 4 when a pass diverges.
int RunDiff(const DiffArgs& args);

}  // namespace rayspace::app
