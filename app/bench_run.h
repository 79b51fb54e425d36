// Runs one `rayspace bench` configuration on one scene at one size: its repetitions, timed.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bench_configs.h"
#include "rayspace/scene.h"
#include "rayspace/frame/render_command.h"

namespace rayspace::app {

// The median of timings (0 for none): the middle one, or the mean of the two middle ones.
double Median(std::vector<double> v);

// One row of the bench table.
struct BenchRow {
  std::string scene;
  int width = 0, height = 0;
  const BenchConfig* config = nullptr;
  std::string skipped;                 // why the configuration did not run (empty: it ran)
  std::vector<double> frame_ms;        // the frame's own time, per repetition
  std::vector<double> search_ms;       // traversal + final tests, per repetition
  std::vector<double> traversal_ms;    // the hierarchy traversal alone, per repetition
  std::vector<std::string> digests;    // per repetition
  std::uint64_t total_tests = 0;
  bool tests_performed = false;        // false: brute force counted (rays x triangles), not performed
  bool tests_counted = true;           // false: the tracer does not count its tests (Embree): no total
  std::size_t peak_rss = 0;            // bytes, over the configuration's repetitions
  std::size_t start_rss = 0;           // bytes resident when the configuration started
  bool peak_reset = false;             // false: peak_rss is the whole process's so far
  RenderArgs args;                     // render's arguments for the configuration

  double MedianMs() const;
  double MedianSearchMs() const;
  double MedianTraversalMs() const;
  std::size_t Pixels() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  std::string Size() const { return std::to_string(width) + "x" + std::to_string(height); }
};

// The row of `config` on a loaded scene at width x height, before any repetition: render's arguments
// from `base` with the configuration's tracer, path and backend, and the oracle off.
BenchRow StartBenchRow(const RenderArgs& base, const BenchConfig& config, const Scene& scene, int width, int height);

// One more frame of the row, timed; false when the row is skipped: a backend that cannot be made or
// cannot hold the frame (no Vulkan device, a build without Vulkan) skips it, with the reason in
// `skipped`. The peak memory is the highest over the row's repetitions, the counter reset before
// each (the process's so far where it cannot be reset), with what was resident when that one started.
bool RunBenchRepetition(BenchRow& row, const Scene& scene, const SceneBuffers& buffers, int repetitions, bool progress);

}  // namespace rayspace::app
