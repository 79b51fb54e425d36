// Runs a reproduce run's configurations: each once, in-process, `jobs` at a time, each result written
// atomically as it finishes, with a progress line on stderr.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "rayspace/scene.h"
#include "rayspace/scene_buffers.h"
#include "rayspace/reproduce/store.h"

namespace rayspace::reproduce {

// What one configuration's frame gives: its counts, its statistics, its phase timings.
struct FrameOutput {
  Counts counts;
  nlohmann::json statistics, timings;
  // The shadow rays traced over all bounces, and those that reach their light (the fit's lit share).
  std::uint64_t shadow_rays = 0, unoccluded_shadow_rays = 0;
};
// Renders one configuration's frame (the `rayspace` executable's frame code; tests pass their own).
using FrameFn = std::function<FrameOutput(const Config&, const Scene&, const SceneBuffers&)>;

// A scene as every configuration of it renders it, loaded once and shared read-only by the jobs.
struct LoadedScene {
  Scene scene;
  SceneBuffers buffers;
  std::string digest;
};

struct Planned {
  Config config;
  std::string key;
  const LoadedScene* scene = nullptr;
};

struct RunOptions {
  std::filesystem::path out;
  int jobs = 1;
  int stop_after = 0;  // > 0: stop as an interrupt would after this many configurations (test use)
  bool progress = false;
};

// Runs every configuration of `todo` and writes its result into out/results. Results do not depend on
// `jobs`: each frame is deterministic and each result is its own file.
void RunPlanned(const std::vector<Planned>& todo, const RunOptions& options, const FrameFn& frame);

}  // namespace rayspace::reproduce
