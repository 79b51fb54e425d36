// `rayspace shadow-bench`: hard shadows through Hunt and Mark's perspective grid against Embree's
// rtcOccluded on the same shadow rays (docs/grids.md, "Speed against Embree").
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "rayspace/exit_codes.h"

namespace rayspace::app {

struct ShadowBenchArgs {
  std::vector<std::string> scenes;
  std::string data, size = "512x512", json;
  int repetitions = 5, threads = 0;
  std::uint32_t grid_cells = 200;
  bool closed_models = false;
};

// Per scene: the first bounce's shadow rays of every point light (rendered once), then per repetition
// the grid's host build, grid.trace on the emulator and Embree's occlusion query on the same rays, each
// timed alone; prints medians, rays per second, their ratio, and how many answers differ (the
// oracle of `render --algo grid` settles who is right).
ExitCode RunShadowBench(const ShadowBenchArgs& args);

}  // namespace rayspace::app
