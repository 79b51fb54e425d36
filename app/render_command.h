#pragma once
#include <cstddef>
#include <string>

#include "exit_codes.h"

namespace rayspace::app {

struct RenderArgs {
  std::string scene, algo = "crsh", size, out, stats, data, direct = "auto", reduction = "hierarchical", backend = "emu";
  int device = -1;
  int threads = 0, subdivision = 8, depth = 2, component_size = 64;
  std::size_t pair_capacity = std::size_t{1} << 24;
  std::size_t split_bytes = 0;
  std::uint32_t max_groups = 0;
  bool depth_given = false;
  bool no_oracle = false, progress = false, timings = false;
};

// Runs `rayspace render`: kOk, or kOracleMismatch when the oracle found rays the frame got wrong.
ExitCode RunRender(const RenderArgs& args);

}  // namespace rayspace::app
