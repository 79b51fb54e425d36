#pragma once
#include <string>

namespace rayspace::app {

struct RenderArgs {
  std::string scene, algo = "brute", size, out, stats, data, direct = "auto";
  int threads = 0;
  bool no_oracle = false, progress = false;
};

// Runs `rayspace render`; returns the exit code (0 ok, 3 when the oracle found mismatches).
int RunRender(const RenderArgs& args);

}  // namespace rayspace::app
