#pragma once
#include <cstddef>
#include <string>

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

// Runs `rayspace render`; returns the exit code (0 ok, 3 when the oracle found mismatches).
int RunRender(const RenderArgs& args);

}  // namespace rayspace::app
